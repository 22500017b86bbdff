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
  // gains log(p_D g(z|x,m)/κ(z)) of the gated pairs
  Eigen::MatrixXd gain =
      Eigen::MatrixXd::Constant(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(J), kLogZero);
  BlockPartition blocks(P + J);
  for (std::size_t p = 0; p < P; ++p) {
    const auto zhat = model.predict(x, M[p]);
    out.p_detect[p] = p_D(model, x, M[p], zhat);
    if (out.p_detect[p] <= 0.0) continue;
    const double log_pd = std::log(out.p_detect[p]);
    for (std::size_t j = 0; j < J; ++j) {
      const auto r = model.residual(Z[j], zhat);
      if (mahalanobis_squared(r, model.noise()) > options.gate) continue;
      gain(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(j)) =
          log_pd + log_gaussian(r, model.noise()) - log_kappa[j];
      blocks.unite(p, P + j);
    }
  }
  // landmarks: log(1 − p_D) when alone; blocks with a measurement go through Murty
  std::vector<std::vector<int>> rows(P + J), cols(P + J);
  for (std::size_t p = 0; p < P; ++p) rows[blocks.find(p)].push_back(static_cast<int>(p));
  for (std::size_t j = 0; j < J; ++j) cols[blocks.find(P + j)].push_back(static_cast<int>(j));
  MurtyOptions murty;
  murty.max_solutions = static_cast<std::size_t>(options.max_assignments);
  murty.max_cost_gap = options.assignment_log_gap;
  double total = constant;
  for (std::size_t b = 0; b < P + J; ++b) {
    const auto& R = rows[b];
    const auto& C = cols[b];
    if (R.empty()) continue;  // clutter only: already in the constant
    if (C.empty()) {
      for (int p : R) total += std::log1p(-out.p_detect[static_cast<std::size_t>(p)]);
      continue;
    }
    Eigen::MatrixXd log_detect(R.size(), C.size());
    Eigen::VectorXd log_miss(R.size());
    for (std::size_t a = 0; a < R.size(); ++a) {
      log_miss(static_cast<Eigen::Index>(a)) = std::log1p(-out.p_detect[static_cast<std::size_t>(R[a])]);
      for (std::size_t c = 0; c < C.size(); ++c)
        log_detect(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(c)) = gain(R[a], C[c]);
    }
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
      for (std::size_t a = 0; a < R.size(); ++a)
        if (h.measurement_of[a] >= 0) beta(static_cast<Eigen::Index>(a), h.measurement_of[a]) += pi;
    }
    for (std::size_t a = 0; a < R.size(); ++a)
      for (std::size_t c = 0; c < C.size(); ++c)
        if (beta(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(c)) > 0.0)
          out.betas.push_back({R[a], C[c], beta(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(c))});
  }
  out.log_likelihood = total;
  return out;
}

}  // namespace glmbslam::backend
