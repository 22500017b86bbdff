// `glmbslam eval`: KITTI devkit metric, ATE and RPE of an estimated trajectory against ground truth.
#include <iostream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "app/cli_checks.hpp"
#include "app/commands.hpp"
#include "core/error.hpp"
#include "eval/association.hpp"
#include "eval/eval_plots.hpp"
#include "eval/report.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {
namespace {

struct EvalArgs {
  std::string gt;
  std::string est;
  std::string json;
  std::string plot_dir;
  std::string format = "kitti";
  double tolerance_s = 0.02;
  std::vector<int> rpe_frames = {1};
  std::vector<double> rpe_distances = {100.0};
  std::string label = "estimate";
};

void run_eval(const EvalArgs& a) {
  const io::TrajectoryFormat format = io::parse_trajectory_format(a.format);
  eval::AssociatedTrajectories pairs;
  if (format == io::TrajectoryFormat::kKitti) {
    pairs = eval::associate_by_index(io::read_kitti_poses(a.gt), io::read_kitti_poses(a.est), a.est);
  } else {
    pairs = eval::associate_by_timestamp(io::read_tum_trajectory(a.gt), io::read_tum_trajectory(a.est),
                                         a.tolerance_s, a.est);
    if (pairs.unmatched_est > 0) {
      spdlog::warn("{}: {} poses have no ground-truth timestamp within {} s and are not evaluated", a.est,
                   pairs.unmatched_est, a.tolerance_s);
    }
  }
  eval::EvaluationOptions options;
  options.rpe_frame_deltas = a.rpe_frames;
  options.rpe_distance_deltas_m = a.rpe_distances;
  const eval::TrajectoryEvaluation e = eval::evaluate_trajectory(pairs.gt, pairs.est, options);
  std::cout << eval::format_table(e) << std::flush;
  if (!a.json.empty()) {
    eval::write_json_file(a.json, eval::to_json(e));
    spdlog::info("metrics written to {}", a.json);
  }
  if (!a.plot_dir.empty()) {
    const auto files = eval::write_evaluation_plots(a.plot_dir, pairs.gt, pairs.est, e, a.label);
    spdlog::info("{} plots written to {}", files.size(), a.plot_dir);
  }
}

}  // namespace

void register_eval_command(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* cmd = app.add_subcommand("eval",
                                 "Evaluate an estimated trajectory against ground truth: KITTI devkit "
                                 "metric (100-800 m and 10-80 m segments), ATE (SE(3)/Sim(3)), RPE");
  cmd->add_option("--gt", args->gt, "ground-truth trajectory file")->required();
  cmd->add_option("--est", args->est, "estimated trajectory file")->required();
  cmd->add_option("--json", args->json, "write the metrics as JSON to this file");
  cmd->add_option("--plot", args->plot_dir, "write PNG plots into this folder");
  cmd->add_option("--format", args->format,
                  "trajectory file format: kitti (one pose per frame, same count) or "
                  "tum (associated by timestamp)")
      ->check(CLI::IsMember({"kitti", "tum"}))
      ->capture_default_str();
  cmd->add_option("--tolerance", args->tolerance_s, "TUM timestamp association tolerance [s]")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--rpe-frames", args->rpe_frames, "RPE frame deltas")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--rpe-distances", args->rpe_distances, "RPE distance deltas [m]")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--label", args->label, "name of the estimate in plot legends")->capture_default_str();
  cmd->callback([args] { run_eval(*args); });
}

}  // namespace glmbslam::app
