#pragma once
// The stereo RFS-ML-SLAM solve of a long run (the refinement's final pass): the EM of RfsMlSlam::solve
// (paper 004 Eq. 6–8 maximised with the associations summed out; E-step β of Eq. 17 from the scan likelihood
// of Eq. 7, 20–22; M-step the β-weighted least squares of Eq. 18), with the same acceptance rule (a round
// that lowers l is halved back up to three times, else undone and the solve stops) and stopping rule, but
// with one Ceres problem for the whole solve (stereo_m_step_problem.hpp): each round only re-weights it.
// Without cardinality moves and for association "rfs" only (the refinement's defaults; RfsMlSlam does the
// rest).
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "backend/mlslam/em_rounds.hpp"
#include "backend/mlslam/landmark_grid.hpp"
#include "backend/mlslam/rfs_ml_slam.hpp"
#include "backend/mlslam/scan_likelihood.hpp"
#include "backend/mlslam/smooth_stereo_detection.hpp"
#include "backend/mlslam/stereo_m_step_problem.hpp"
#include "backend/mlslam/stereo_ml_slam.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::backend {

class StereoBatchMlSlam {
 public:
  using PoseList = StereoMlSlam::PoseList;
  using LandmarkList = StereoMlSlam::LandmarkList;
  using ControlList = StereoMlSlam::ControlList;
  using MeasurementSet = StereoMlSlam::MeasurementSet;

  /// Throws ConfigError on an invalid config, std::invalid_argument on one this solver does not do
  /// (cardinality moves, nearest-neighbour associations).
  StereoBatchMlSlam(const Se3Motion& motion, const StereoMeasurementModel& model, const MlSlamConfig& config)
      : motion_(motion), model_(model), config_(config), p_D_(StereoMlSlamParts::detection(model, config)) {
    validate_mlslam_config(config_);
    if (!supports(config_))
      throw std::invalid_argument(
          "StereoBatchMlSlam: no cardinality moves, association rfs and the configured motion noise only");
  }

  static bool supports(const MlSlamConfig& c) {
    return !c.cardinality_moves && c.association == "rfs" && c.motion_noise == "configured";
  }

  /// As RfsMlSlam::set_stop: asked before every EM round; true ends the solve with the last round's estimate.
  void set_stop(std::function<bool()> stop) { stop_ = std::move(stop); }

  /// Refines `poses` (x_0 held) and `map` in place; as RfsMlSlam::solve.
  MlSlamReport solve(PoseList& poses, const ControlList& controls, const std::vector<MeasurementSet>& scans,
                     LandmarkList& map) const {
    if (poses.empty() || poses.size() != scans.size() || controls.size() != scans.size())
      throw std::invalid_argument(
          "StereoBatchMlSlam: poses, controls and scans must have the same non-zero length");
    Stopwatch watch;
    MlSlamReport report;
    StereoMStepProblem problem(motion_, model_, controls, map.size(), config_);
    State s{poses, map, {}, {}, 0.0};
    auto timed_e_step = [&](State& state) {
      Stopwatch e;
      e_step(state, controls, scans);
      report.e_step_ms += e.elapsed_ms();
    };
    run_em_rounds(
        s, config_, false, timed_e_step,
        [&](State& next) {
          Stopwatch m;
          m_step(problem, next, scans);
          report.m_step_ms += m.elapsed_ms();
        },
        blend_towards<Se3Motion, State>, [](State&) { return 0; }, stop_, report);
    report.ms = watch.elapsed_ms();
    poses = std::move(s.poses);
    map = std::move(s.map);
    return report;
  }

  /// l of Eq. 8 at the given estimate.
  double log_likelihood(const PoseList& poses, const ControlList& controls,
                        const std::vector<MeasurementSet>& scans, const LandmarkList& map) const {
    State s{poses, map, {}, {}, 0.0};
    e_step(s, controls, scans);
    return s.log_likelihood;
  }

 private:
  using State = EmState<PoseList, LandmarkList>;
  using ScanState = typename State::Scan;

  /// β and l at the current estimate (parallel over scans; each scan writes only its own slot).
  void e_step(State& s, const ControlList& controls, const std::vector<MeasurementSet>& scans) const {
    const std::size_t K = scans.size();
    s.scans.resize(K);
    s.motion_ll.assign(K, 0.0);
    ScanLikelihoodOptions o;
    o.gate = config_.gate;
    o.max_assignments = config_.max_assignments;
    o.assignment_log_gap = config_.assignment_log_gap;
    // candidates: the landmarks of the grid cells meeting the box of the camera's frustum (cells of 1/8 of
    // the query radius: a box a few cells wide), then maybe_in_view, as RfsMlSlam (the same set)
    const LandmarkGrid<3> grid(
        s.map.size(), [&](std::size_t j) { return s.map[j]; }, p_D_.query_radius() / 8.0);
    parallel_for(K, [&](std::size_t i) {
      ScanState& ss = s.scans[i];
      const auto box = p_D_.view_box(model_, s.poses[i]);
      ss.candidates = grid.in_box_if(box.first, box.second, [&](int j) {
        return p_D_.maybe_in_view(model_, s.poses[i], s.map[static_cast<std::size_t>(j)]);
      });
      LandmarkList M;
      M.reserve(ss.candidates.size());
      for (int j : ss.candidates) M.push_back(s.map[static_cast<std::size_t>(j)]);
      ss.association = evaluate_scan(model_, p_D_, s.poses[i], M, scans[i], o);
      if (i > 0) s.motion_ll[i] = motion_.log_density(s.poses[i], s.poses[i - 1], controls[i]);
    });
    s.log_likelihood = 0.0;
    for (std::size_t i = 0; i < K; ++i)
      s.log_likelihood += s.motion_ll[i] + s.scans[i].association.log_likelihood;
  }

  /// One M-step: the problem re-weighted by this round's β (those ≥ min_responsibility, as RfsMlSlam), then
  /// Levenberg–Marquardt.
  void m_step(StereoMStepProblem& problem, State& s, const std::vector<MeasurementSet>& scans) const {
    problem.clear_weights();
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const ScanState& ss = s.scans[i];
      for (const auto& b : ss.association.betas) {
        if (b.beta < config_.min_responsibility) continue;
        problem.add(i, ss.candidates[static_cast<std::size_t>(b.landmark)],
                    scans[i][static_cast<std::size_t>(b.measurement)], b.beta);
      }
    }
    problem.solve(s.poses, s.map);
  }

  Se3Motion motion_;
  StereoMeasurementModel model_;
  MlSlamConfig config_;
  SmoothStereoDetection p_D_;
  std::function<bool()> stop_;
};

}  // namespace glmbslam::backend
