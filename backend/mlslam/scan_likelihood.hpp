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

/// A scan's blocks that hold a gated pair, laid out flat (no allocation per landmark): per block its
/// landmarks and measurements (ascending) and pairs, and each node's position in its block. A block's root is
/// its smallest node, always a landmark.
struct ScanBlocks {
  template <class T>
  struct Span {
    const T* first;
    const T* last;
    std::size_t size() const { return static_cast<std::size_t>(last - first); }
    const T& operator[](std::size_t k) const { return first[k]; }
    const T* begin() const { return first; }
    const T* end() const { return last; }
  };

  ScanBlocks(BlockPartition& blocks, const std::vector<GatedPair>& gated, std::size_t P, std::size_t J)
      : block_of_root(P, -1), local(P + J, -1) {
    int n = 0;
    for (const auto& g : gated) {
      const std::size_t root = blocks.find(static_cast<std::size_t>(g.landmark));
      if (block_of_root[root] < 0) block_of_root[root] = n++;
    }
    const auto B = static_cast<std::size_t>(n);
    std::vector<int> node_block(P + J, -1);
    for (std::size_t v = 0; v < P + J; ++v) {
      const std::size_t root = blocks.find(v);
      if (root < P) node_block[v] = block_of_root[root];
    }
    counting_sort(
        B, P, [&](std::size_t p) { return node_block[p]; }, [](std::size_t p) { return static_cast<int>(p); },
        [&](std::size_t p, int at) { local[p] = at; }, row_start_, row_items_);
    counting_sort(
        B, J, [&](std::size_t j) { return node_block[P + j]; },
        [](std::size_t j) { return static_cast<int>(j); }, [&](std::size_t j, int at) { local[P + j] = at; },
        col_start_, col_items_);
    counting_sort(
        B, gated.size(),
        [&](std::size_t k) { return node_block[static_cast<std::size_t>(gated[k].landmark)]; },
        [&](std::size_t k) { return &gated[k]; }, [](std::size_t, int) {}, pair_start_, pair_items_);
  }

  Span<int> rows(int b) const { return span(row_items_, row_start_, b); }
  Span<int> cols(int b) const { return span(col_items_, col_start_, b); }
  Span<const GatedPair*> pairs(int b) const { return span(pair_items_, pair_start_, b); }

  std::vector<int>
      block_of_root;       ///< per landmark: its block's id if it is the root of one with a pair, else −1
  std::vector<int> local;  ///< position of a landmark in its block's rows, of a measurement in its cols

 private:
  /// Items 0..n−1 grouped by bucket_of(k) ∈ [0, B) (−1: left out), stably: `start` gets the B + 1 offsets,
  /// `items` value_of(k) in bucket order, and placed(k, position of k in its bucket) is called for each.
  template <class T, class BucketOf, class ValueOf, class Placed>
  static void counting_sort(std::size_t B, std::size_t n, BucketOf&& bucket_of, ValueOf&& value_of,
                            Placed&& placed, std::vector<int>& start, std::vector<T>& items) {
    start.assign(B + 1, 0);
    for (std::size_t k = 0; k < n; ++k)
      if (bucket_of(k) >= 0) ++start[static_cast<std::size_t>(bucket_of(k)) + 1];
    for (std::size_t b = 0; b < B; ++b) start[b + 1] += start[b];
    items.resize(static_cast<std::size_t>(start[B]));
    std::vector<int> next(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < n; ++k) {
      if (bucket_of(k) < 0) continue;
      const auto b = static_cast<std::size_t>(bucket_of(k));
      placed(k, next[b] - start[b]);
      items[static_cast<std::size_t>(next[b]++)] = value_of(k);
    }
  }

  template <class T>
  static Span<T> span(const std::vector<T>& items, const std::vector<int>& start, int b) {
    const auto k = static_cast<std::size_t>(b);
    return {items.data() + start[k], items.data() + start[k + 1]};
  }

  std::vector<int> row_start_, col_start_, pair_start_, row_items_, col_items_;
  std::vector<const GatedPair*> pair_items_;
};

/// A block of one landmark and one measurement: log of Σ_θ over its two assignments (detected with `gain`,
/// or missed with `log_miss` and the measurement clutter), as rank_associations and log_sum_exp would give it
/// to the last bit (Murty's order, its gap and count limits, the sum from the best term), and the pair's β
/// handed to `beta` when `marginals`.
template <class OnBeta>
double one_pair_block(double gain, double log_miss, const MurtyOptions& murty, bool marginals,
                      OnBeta&& beta) {
  const bool detect_best = !(log_miss > gain);
  const double best = detect_best ? gain : log_miss, other = detect_best ? log_miss : gain;
  // Murty ranks by cost −log w; the second assignment is kept if feasible, within the gap and allowed
  const bool both =
      murty.max_solutions >= 2 && other != kLogZero && !((-other) - (-best) > murty.max_cost_gap);
  const double block_ll = both ? best + std::log(1.0 + std::exp(other - best)) : best;  // log_sum_exp's sum
  if (marginals && (detect_best || both)) {
    const double b = std::exp(gain - block_ll);
    if (b > 0.0) beta(b);
  }
  return block_ll;
}

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
  // landmarks: log(1 − p_D) when alone; blocks with a measurement go through Murty, summed in the order of
  // their roots
  const ScanBlocks layout(blocks, pairs, P, J);
  MurtyOptions murty;
  murty.max_solutions = static_cast<std::size_t>(options.max_assignments);
  murty.max_cost_gap = options.assignment_log_gap;
  double total = constant;
  for (std::size_t root = 0; root < P; ++root) {
    if (blocks.find(root) != root) continue;
    const int b = layout.block_of_root[root];
    if (b < 0) {  // a landmark alone: missed
      total += std::log1p(-out.p_detect[root]);
      continue;
    }
    const auto Rb = layout.rows(b);
    const auto Cb = layout.cols(b);
    if (Rb.size() == 1 && Cb.size() == 1) {  // one landmark, one measurement: the two assignments directly
      const double gain = (*layout.pairs(b).begin())->gain;
      total += one_pair_block(gain, std::log1p(-out.p_detect[static_cast<std::size_t>(Rb[0])]), murty,
                              options.marginals, [&](double beta) {
                                out.betas.push_back({Rb[0], Cb[0], beta});
                              });
      continue;
    }
    Eigen::MatrixXd log_detect(Rb.size(), Cb.size());
    Eigen::VectorXd log_miss(Rb.size());
    for (std::size_t a = 0; a < Rb.size(); ++a)
      log_miss(static_cast<Eigen::Index>(a)) = std::log1p(-out.p_detect[static_cast<std::size_t>(Rb[a])]);
    log_detect.setConstant(kLogZero);
    for (const GatedPair* g : layout.pairs(b))
      log_detect(layout.local[static_cast<std::size_t>(g->landmark)],
                 layout.local[P + static_cast<std::size_t>(g->measurement)]) = g->gain;
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
