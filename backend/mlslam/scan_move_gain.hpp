#pragma once
// The change of one scan's log-likelihood log p(Z | x, M) (paper 004 Eq. 7, scan_likelihood.hpp) when some
// landmarks leave the map and others join it: the Δl of a cardinality move (death, merge, birth) on that
// scan.
//
// Eq. 7 factorises over the blocks of the gated landmark–measurement graph (its connected components), and
// the clutter term e^{−λ_c} Π κ(z) does not depend on the map. A block that holds no changed landmark is the
// same before and after the move and cancels. So the gain is computed on the closure of the changed landmarks
// in the union of both graphs (the landmarks and measurements reachable from them through gated pairs, before
// or after): every block that differs lies inside it, every block that meets it lies wholly inside it, and
// the difference of the two evaluations over it is exact. A move touches a few landmarks of a scan with
// hundreds, so this costs a few gating tests and two small ranked-assignment sums instead of two whole scans.
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "backend/mlslam/scan_likelihood.hpp"

namespace glmbslam::backend {

/// log p(Z | x, M′) − log p(Z | x, M), where M′ is M without the landmarks at the positions `removed` plus
/// `added`; `M` holds the scan's candidates as evaluate_scan received them.
template <class Model, class Detection, class LandmarkList, class MeasurementList>
double scan_move_gain(const Model& model, const Detection& p_D, const typename Model::Pose& x,
                      const LandmarkList& M, const std::vector<int>& removed, const LandmarkList& added,
                      const MeasurementList& Z, const ScanLikelihoodOptions& options) {
  const std::size_t P = M.size(), A = added.size(), U = P + A, J = Z.size();
  auto landmark = [&](std::size_t u) -> const auto& {
    return u < P ? M[u] : added[u - P];
  };
  const auto& R = model.noise();
  const Eigen::LLT<typename std::decay_t<decltype(R)>::PlainObject> llt(R);
  const bool gating = llt.info() == Eigen::Success;  // as evaluate_scan: no pair without a factorised R
  // the gating test of evaluate_scan (p_D > 0 and within the gate), its prediction computed once per landmark
  using Prediction =
      std::decay_t<decltype(model.predict(x, std::declval<const typename LandmarkList::value_type&>()))>;
  std::vector<Prediction> zhat(gating ? U : 0);
  std::vector<char> predicted(U, 0), seen(U, 0);
  auto gated = [&](std::size_t u, std::size_t j) {
    if (!predicted[u]) {
      zhat[u] = model.predict(x, landmark(u));
      predicted[u] = p_D(model, x, landmark(u), zhat[u]) > 0.0 ? 1 : 2;
    }
    if (predicted[u] != 1) return false;
    const double d2 = llt.matrixL().solve(model.residual(Z[j], zhat[u])).squaredNorm();
    return d2 <= options.gate;
  };
  std::vector<char> in_closure(J, 0);
  std::vector<std::size_t> landmarks, measurements;
  for (int r : removed) {
    const auto u = static_cast<std::size_t>(r);
    if (u < P && !seen[u]) seen[u] = 1, landmarks.push_back(u);
  }
  for (std::size_t u = P; u < U; ++u) seen[u] = 1, landmarks.push_back(u);
  if (gating) {
    for (std::size_t l = 0, m = 0; l < landmarks.size() || m < measurements.size();) {
      for (; l < landmarks.size(); ++l)
        for (std::size_t j = 0; j < J; ++j)
          if (!in_closure[j] && gated(landmarks[l], j)) in_closure[j] = 1, measurements.push_back(j);
      for (; m < measurements.size(); ++m)
        for (std::size_t u = 0; u < U; ++u)
          if (!seen[u] && gated(u, measurements[m])) seen[u] = 1, landmarks.push_back(u);
    }
  }
  std::vector<char> gone(P, 0);
  for (int r : removed)
    if (static_cast<std::size_t>(r) < P) gone[static_cast<std::size_t>(r)] = 1;
  LandmarkList before, after;
  for (std::size_t u = 0; u < U; ++u) {
    if (!seen[u]) continue;
    if (u < P) before.push_back(M[u]);
    if (u >= P || !gone[u]) after.push_back(landmark(u));
  }
  MeasurementList Zc;
  for (std::size_t j = 0; j < J; ++j)
    if (in_closure[j]) Zc.push_back(Z[j]);
  ScanLikelihoodOptions o = options;
  o.marginals = false;
  return evaluate_scan(model, p_D, x, after, Zc, o).log_likelihood -
         evaluate_scan(model, p_D, x, before, Zc, o).log_likelihood;
}

}  // namespace glmbslam::backend
