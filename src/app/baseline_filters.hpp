#pragma once
// The baseline filters of `glmbslam sim` and `glmbslam run` (Victoria Park, stereo) beside δ-GLMB-SLAM:
//   lmb              LMB-SLAM with the optimal-kernel proposal (backend/lmb/lmb_slam.hpp)
//   lmb1             LMB-SLAM with the prior proposal
//   fastslam2        FastSLAM 2.0 with maximum-likelihood association (backend/fastslam/fastslam2.hpp)
//   fastslam2-known  FastSLAM 2.0 with the simulators' true landmark labels (the oracle row of paper 003;
//                    simulations only)
// Their settings: the YAML sections "lmb" (LmbConfig) and "fastslam" (FastSlamConfig); LMB-SLAM also reads
// the δ-GLMB particle-filter section "rbpf" (proposal settings, map update), FastSLAM takes particles and
// seed from it.
#include <string>
#include <utility>
#include <vector>

#include "app/baseline_configs.hpp"
#include "backend/fastslam/fastslam2.hpp"
#include "backend/lmb/lmb_slam.hpp"
#include "backend/rbpf/rbpf_config.hpp"

namespace glmbslam::app {

/// Passes the true landmark label of each measurement (−1 = clutter) to filters that take them (FastSLAM 2.0;
/// used only with "known" association); other filters ignore them.
template <class Slam>
auto set_true_labels(Slam& slam, const std::vector<int>& labels, int)
    -> decltype(slam.set_measurement_labels(labels), void()) {
  slam.set_measurement_labels(labels);
}
template <class Slam>
void set_true_labels(Slam& /*slam*/, const std::vector<int>& /*labels*/, long) {}

/// Builds the baseline filter `algorithm` (is_baseline_algorithm) and returns use(filter). Particles and
/// seed come from `rbpf`.
template <class Motion, class Meas, class Use>
auto with_baseline_filter(const std::string& algorithm, const Motion& motion, const Meas& model,
                          backend::RbpfConfig rbpf, const BaselineConfigs& configs,
                          const typename Motion::State& initial_pose, Use&& use) {
  if (algorithm == "lmb" || algorithm == "lmb1") {
    rbpf.proposal = algorithm == "lmb1" ? "prior" : "optimal";
    backend::LmbSlam<Motion, Meas> slam(motion, model, rbpf, configs.lmb, initial_pose);
    return use(slam);
  }
  backend::FastSlamConfig fc = configs.fastslam;
  fc.particles = rbpf.particles;
  fc.seed = rbpf.seed;
  fc.association = algorithm == "fastslam2-known" ? "known" : "ml";
  backend::FastSlam2<Motion, Meas> slam(motion, model, fc, initial_pose);
  return use(slam);
}

}  // namespace glmbslam::app
