#pragma once
// The full trajectory evaluation of `glmbslam eval` (and of `run`): KITTI devkit metric (standard and short
// lengths), ATE (SE(3)/Sim(3)), RPE at frame and distance deltas; its JSON block and its text table.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/types.hpp"
#include "eval/alignment.hpp"
#include "eval/kitti_metric.hpp"
#include "eval/rpe.hpp"

namespace glmbslam::eval {

struct EvaluationOptions {
  std::vector<double> kitti_lengths = kitti_standard_lengths();
  std::vector<double> kitti_short_lengths = eval::kitti_short_lengths();
  int kitti_step_frames = 10;
  std::vector<int> rpe_frame_deltas = {1};
  std::vector<double> rpe_distance_deltas_m = {100.0};
};

struct TrajectoryEvaluation {
  int frames = 0;
  double path_length_m = 0.0;  ///< length of the ground-truth path
  KittiResult kitti;           ///< standard lengths 100…800 m
  KittiResult kitti_short;     ///< short lengths 10…80 m (for short drives)
  AteResult ate;
  std::vector<RpeResult> rpe_frames;     ///< one per options.rpe_frame_deltas
  std::vector<RpeResult> rpe_distances;  ///< one per options.rpe_distance_deltas_m
};

/// Evaluates `est` against `gt` (same size ≥ 1; std::invalid_argument otherwise).
TrajectoryEvaluation evaluate_trajectory(const PoseList& gt, const PoseList& est,
                                         const EvaluationOptions& options = EvaluationOptions());

/// JSON with the design.md keys: frames, path_length_m, kitti.{t_rel_percent, r_rel_deg_per_100m, segments,
/// per_length[{length_m, segments, t_rel_percent, r_rel_deg_per_100m}]}, kitti_short.{same},
/// ate.{poses, se3_rmse_m, sim3_rmse_m, sim3_scale}, rpe.{delta_frames, pairs, trans_rmse_m, trans_mean_m,
/// rot_rmse_deg, rot_mean_deg (for the first frame delta), by_frame_delta[...], by_distance[{delta_m, ...}]}.
/// Undefined values (no segment fits in the path) are null.
nlohmann::json to_json(const TrajectoryEvaluation& e);
nlohmann::json to_json(const KittiResult& k);
nlohmann::json to_json(const AteResult& a);

/// A human-readable table of the evaluation.
std::string format_table(const TrajectoryEvaluation& e);

/// Writes `j` pretty-printed (indent 2) to `path`, atomically.
void write_json_file(const std::string& path, const nlohmann::json& j);

}  // namespace glmbslam::eval
