#pragma once
// The EM rounds shared by the RFS-ML-SLAM solvers (rfs_ml_slam.hpp, stereo_batch_ml_slam.hpp): paper 004's
// l of Eq. 8 maximised by alternating the M-step (β-weighted least squares, Eq. 18) and the E-step (β of
// Eq. 17 and l at the new estimate). The M-step holds p_D fixed, so a round that lowers l is halved back
// towards the previous estimate up to three times, else undone and the solve stops; the solve also stops
// when a round adds less than max(tolerance, relative_tolerance × the rise since the start) and no
// cardinality move was accepted, or before a round when the caller's stop predicate is true (an interrupted
// run: the estimate is then the last completed round's, whose l is the highest so far).
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "backend/mlslam/mlslam_config.hpp"
#include "backend/mlslam/scan_likelihood.hpp"

namespace glmbslam::backend {

/// The estimate the EM rounds move, with its E-step: per scan the candidate landmarks (map indices,
/// ascending) and their association, the motion terms, and l of Eq. 8.
template <class PoseList, class LandmarkList>
struct EmState {
  struct Scan {
    std::vector<int> candidates;
    ScanAssociation association;
  };
  PoseList poses;
  LandmarkList map;
  std::vector<Scan> scans;
  std::vector<double> motion_ll;
  double log_likelihood = 0.0;
  /// s of the motion noise s·Q (MlSlamConfig::motion_noise "estimated": the M-step's ML estimate; else 1)
  double motion_scale = 1.0;
};

/// next ← midway between `from` and `next` (poses in Motion's tangent space; landmarks both maps hold).
template <class Motion, class State>
void blend_towards(const State& from, State& next) {
  for (std::size_t i = 0; i < next.poses.size(); ++i)
    next.poses[i] = Motion::retract(from.poses[i], 0.5 * Motion::local(next.poses[i], from.poses[i]));
  for (std::size_t j = 0; j < next.map.size() && j < from.map.size(); ++j)
    next.map[j] = 0.5 * (next.map[j] + from.map[j]);
}

/// Runs the rounds from `s` (State has poses, map, log_likelihood) and leaves the estimate in `s`.
/// `e_step(State&)` sets β and l; `m_step(State&)` moves the estimate; `moves(State&)` tries cardinality
/// moves after a round and returns how many it accepted. `keep_every_step`: every M-step is kept, without
/// halving (vector ML with nearest-neighbour association, whose l is not what its M-step raises). `stop`
/// (may be empty) is asked before every round; when it says true the rounds end and report.stopped is set.
/// Sets the report's (MlSlamReport's) rounds and initial / final / per-round log-likelihoods.
template <class State, class EStep, class MStep, class Blend, class Moves, class Report>
void run_em_rounds(State& s, const MlSlamConfig& config, bool keep_every_step, EStep&& e_step, MStep&& m_step,
                   Blend&& blend, Moves&& moves, const std::function<bool()>& stop, Report& report) {
  e_step(s);
  report.initial_log_likelihood = s.log_likelihood;
  double l = s.log_likelihood;
  for (int round = 0; round < config.max_rounds; ++round) {
    if (stop && stop()) {
      report.stopped = true;
      break;
    }
    State next = s;
    m_step(next);
    e_step(next);
    for (int halving = 0; halving < 3 && !keep_every_step && !(next.log_likelihood > l); ++halving) {
      blend(s, next);
      e_step(next);
    }
    const bool improved = next.log_likelihood > l;
    if (improved || keep_every_step) s = std::move(next);
    const int accepted = moves(s);
    ++report.rounds;
    const double gain = s.log_likelihood - l;
    l = s.log_likelihood;
    report.log_likelihood_per_round.push_back(l);
    const double stop_gain =
        std::max(config.tolerance, config.relative_tolerance * (l - report.initial_log_likelihood));
    if (accepted == 0 && (!improved || std::abs(gain) < stop_gain)) break;
  }
  report.final_log_likelihood = l;
}

}  // namespace glmbslam::backend
