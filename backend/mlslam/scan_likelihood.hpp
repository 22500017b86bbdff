#pragma once
// The RFS measurement likelihood of one scan, p(Z_i | x_i, M) (paper 004 Eq. 7), with the associations summed
// out, and the marginal association probabilities β_mn = Σ_θ π_θ 1[θ(m) = n] (the E-step of digest 3.5
// option B).
//
//   p(Z | x, M) = e^{−λ_c} Π_{z∈Z} κ(z) · Σ_θ Π_{m undetected} (1 − p_D(m|x)) Π_{(m,z)∈θ} p_D(m|x)
//   g(z|x,m)/κ(z)
//
// (Eq. 20–21 in log form). Pairs beyond the Mahalanobis gate are dropped; the landmark-measurement graph is
// split into independent blocks (connected components), and each block's sum over θ is taken over its
// ranked assignments (Murty, backend/rbpf/murty.hpp), best first, which is the stable form of Eq. 22: the
// best assignment's log weight plus the log of the (≥ 0) correction factor. With enough assignments per block
// the sum is exact; a truncated sum is a lower bound.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "backend/rbpf/murty.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"

namespace glmbslam::backend {

/// β of one landmark-measurement pair.
struct Responsibility {
  int landmark = 0;     ///< index into the candidate list given to evaluate_scan
  int measurement = 0;  ///< index into Z
  double beta = 0.0;
};

struct ScanAssociation {
  double log_likelihood = 0.0;        ///< log p(Z | x, M)
  std::vector<double> p_detect;       ///< p_D of each candidate landmark
  std::vector<Responsibility> betas;  ///< β > 0 of the gated pairs
};

/// A landmark-measurement pair within the gate and its gain log(p_D g(z|x,m)/κ(z)).
struct GatedPair {
  int landmark = 0, measurement = 0;
  double gain = 0.0;
};

struct ScanLikelihoodOptions {
  double gate = 16.0;               ///< squared Mahalanobis gate
  int max_assignments = 50;         ///< ranked assignments per block
  double assignment_log_gap = 9.2;  ///< stop below e^{-gap} of the best assignment
  bool marginals = true;            ///< compute β (false: the likelihood only)
};

/// Union-find over the landmark (0..P−1) and measurement (P..P+J−1) nodes of a scan.
class BlockPartition {
 public:
  explicit BlockPartition(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

/// log p(Z | x, M) of Eq. 7 and the β of the gated pairs, for the candidate landmarks `M` (those possibly in
/// view; landmarks with p_D = 0 contribute nothing and may be left out). `p_D(model, x, m, ẑ)` is the
/// detection probability (SmoothDetection2D, SmoothStereoDetection).
template <class Model, class Detection, class LandmarkList, class MeasurementList>
ScanAssociation evaluate_scan(const Model& model, const Detection& p_D, const typename Model::Pose& x,
                              const LandmarkList& M, const MeasurementList& Z,
                              const ScanLikelihoodOptions& options) {
  const std::size_t P = M.size(), J = Z.size();
  ScanAssociation out;
  out.p_detect.resize(P);
  double constant = -model.clutter_rate();  // −∫κ
  std::vector<double> log_kappa(J);
  for (std::size_t j = 0; j < J; ++j) {
    log_kappa[j] = model.log_clutter_intensity(Z[j]);
    constant += log_kappa[j];
  }
  // gains log(p_D g(z|x,m)/κ(z)) of the gated pairs. R is factorised once per scan; a pair can pass the gate
  // only if |r_0| ≤ √(gate R_00) (Cauchy–Schwarz: r_0² ≤ (rᵀR⁻¹r) R_00), so each landmark looks only at the
  // measurements of that window of z_0 (sorted once), not at all of Z. Both models' residual component 0 is
  // z_0 − ẑ_0 (range, u_L), never wrapped.
  const auto& R = model.noise();
  const Eigen::LLT<typename std::decay_t<decltype(R)>::PlainObject> llt(R);
  std::vector<GatedPair> pairs;
  BlockPartition blocks(P + J);
  if (llt.info() == Eigen::Success) {
    double log_det = 0.0;
    for (Eigen::Index i = 0; i < R.rows(); ++i) log_det += std::log(llt.matrixLLT()(i, i));
    const double log_norm = -0.5 * (static_cast<double>(R.rows()) * std::log(2.0 * M_PI) + 2.0 * log_det);
    const double window = std::sqrt(options.gate * R(0, 0)) * (1.0 + 1e-9) + 1e-12;
    std::vector<std::size_t> order(J);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return Z[a](0) < Z[b](0); });
    std::vector<double> key(J);
    for (std::size_t k = 0; k < J; ++k) key[k] = Z[order[k]](0);
    for (std::size_t p = 0; p < P; ++p) {
      const auto zhat = model.predict(x, M[p]);
      out.p_detect[p] = p_D(model, x, M[p], zhat);
      if (out.p_detect[p] <= 0.0) continue;
      const double log_pd = std::log(out.p_detect[p]);
      const auto lo = std::lower_bound(key.begin(), key.end(), zhat(0) - window);
      const auto hi = std::upper_bound(lo, key.end(), zhat(0) + window);
      for (auto it = lo; it != hi; ++it) {
        const std::size_t j = order[static_cast<std::size_t>(it - key.begin())];
        const auto r = model.residual(Z[j], zhat);
        const double d2 = llt.matrixL().solve(r).squaredNorm();
        if (!(d2 <= options.gate)) continue;
        pairs.push_back(
            {static_cast<int>(p), static_cast<int>(j), log_pd + log_norm - 0.5 * d2 - log_kappa[j]});
        blocks.unite(p, P + j);
      }
    }
  } else {
    for (std::size_t p = 0; p < P; ++p) out.p_detect[p] = p_D(model, x, M[p], model.predict(x, M[p]));
  }
  // landmarks: log(1 − p_D) when alone; blocks with a measurement go through Murty
  std::vector<std::vector<int>> rows(P + J), cols(P + J);
  std::vector<int> local(P + J, -1);  // position of a landmark in its block's rows, of a measurement in cols
  for (std::size_t p = 0; p < P; ++p) {
    auto& r = rows[blocks.find(p)];
    local[p] = static_cast<int>(r.size());
    r.push_back(static_cast<int>(p));
  }
  for (std::size_t j = 0; j < J; ++j) {
    auto& c = cols[blocks.find(P + j)];
    local[P + j] = static_cast<int>(c.size());
    c.push_back(static_cast<int>(j));
  }
  std::vector<std::vector<const GatedPair*>> block_pairs(P + J);
  for (const auto& g : pairs) block_pairs[blocks.find(static_cast<std::size_t>(g.landmark))].push_back(&g);
  MurtyOptions murty;
  murty.max_solutions = static_cast<std::size_t>(options.max_assignments);
  murty.max_cost_gap = options.assignment_log_gap;
  double total = constant;
  for (std::size_t b = 0; b < P + J; ++b) {
    const auto& Rb = rows[b];
    const auto& Cb = cols[b];
    if (Rb.empty()) continue;  // clutter only: already in the constant
    if (Cb.empty()) {
      for (int p : Rb) total += std::log1p(-out.p_detect[static_cast<std::size_t>(p)]);
      continue;
    }
    Eigen::MatrixXd log_detect(Rb.size(), Cb.size());
    Eigen::VectorXd log_miss(Rb.size());
    for (std::size_t a = 0; a < Rb.size(); ++a)
      log_miss(static_cast<Eigen::Index>(a)) = std::log1p(-out.p_detect[static_cast<std::size_t>(Rb[a])]);
    log_detect.setConstant(kLogZero);
    for (const GatedPair* g : block_pairs[b])
      log_detect(local[static_cast<std::size_t>(g->landmark)],
                 local[P + static_cast<std::size_t>(g->measurement)]) = g->gain;
    const auto hyps = rank_associations(log_detect, log_miss, murty);
    std::vector<double> lw;
    lw.reserve(hyps.size());
    for (const auto& h : hyps) lw.push_back(h.log_weight);
    const double block_ll = log_sum_exp(lw);
    total += block_ll;
    if (!options.marginals || hyps.empty()) continue;
    Eigen::MatrixXd beta = Eigen::MatrixXd::Zero(log_detect.rows(), log_detect.cols());
    for (const auto& h : hyps) {
      const double pi = std::exp(h.log_weight - block_ll);
      for (std::size_t a = 0; a < Rb.size(); ++a)
        if (h.measurement_of[a] >= 0) beta(static_cast<Eigen::Index>(a), h.measurement_of[a]) += pi;
    }
    for (std::size_t a = 0; a < Rb.size(); ++a)
      for (std::size_t c = 0; c < Cb.size(); ++c)
        if (beta(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(c)) > 0.0)
          out.betas.push_back(
              {Rb[a], Cb[c], beta(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(c))});
  }
  out.log_likelihood = total;
  return out;
}

}  // namespace glmbslam::backend
