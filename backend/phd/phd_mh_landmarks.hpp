#pragma once
// The landmark-gathering step of the multi-hypothesis importance density (backend/rbpf/mh_proposal.hpp, step
// 1) for a GM-PHD map: PHD-SLAM 3.0 (paper 003; digest 2.4). Every GM component within query_radius + margin
// of the predicted pose with p_D(mean) > 0 is one landmark of the MH-ID, with weight η = the component's GM
// weight (the core caps it at 1) and the component's mean and covariance. Found by argument-dependent lookup
// from MhProposal::build, so including this header is all PhdSlam needs.
// Note: the core's miss term is the Bernoulli form log(1 − η p_D) for every map; paper 003's code uses
// log(1 − p_D) for a GM component (η only in the detection entries, digest 2.4). Both agree for η = 1; for a
// weak component (e.g. a fresh birth, η = 1e-6) ours makes "missed" nearly free instead of costing 1 − p_D in
// every assignment (a common factor there unless the component is detected in some assignment).
#include "backend/phd/gm_phd_map.hpp"
#include "backend/rbpf/mh_proposal.hpp"

namespace glmbslam::backend {

template <class Meas>
void gather_mh_landmarks(const GmPhdMap<Meas>& map, const Meas& model, const typename Meas::Pose& x_pred,
                         double margin, MhLandmarkList<Meas>& out) {
  out.clear();
  const auto p = Meas::position(x_pred);
  const double r = model.query_radius() + margin;
  for (const auto& c : map.components) {
    if ((Meas::landmark_position(c.mean) - p).squaredNorm() > r * r) continue;
    if (!(model.detection_probability(x_pred, c.mean) > 0.0)) continue;
    MhLandmark<Meas> lm;
    lm.mean = c.mean;
    lm.cov = c.cov;
    lm.weight = c.weight;
    out.push_back(lm);
  }
}

}  // namespace glmbslam::backend
