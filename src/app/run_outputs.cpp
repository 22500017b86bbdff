#include "app/run_outputs.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "app/ground_truth_output.hpp"
#include "app/run_report.hpp"
#include "core/atomic_file.hpp"
#include "core/stopwatch.hpp"
#include "eval/eval_plots.hpp"
#include "eval/line_plot.hpp"
#include "eval/masked_evaluation.hpp"
#include "eval/report.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {
namespace {

void write_map_plot(const std::string& path, const RunRecord& r) {
  eval::LinePlot plot("Map and trajectory (top view)", "x [m]", "z [m]");
  plot.set_equal_aspect(true);
  std::vector<double> mx, mz;
  for (const auto& p : r.map) {
    mx.push_back(p.position.x());
    mz.push_back(p.position.z());
  }
  plot.add_series(mx, mz, eval::colours::kGrey, "landmarks", eval::SeriesStyle::kMarkers, 1);
  auto add_path = [&](const PoseList& poses, eval::Rgb colour, const std::string& label) {
    std::vector<double> x, z;
    for (const auto& T : poses) {
      x.push_back(T.translation().x());
      z.push_back(T.translation().z());
    }
    plot.add_series(x, z, colour, label);
  };
  if (r.ground_truth) add_path(*r.ground_truth, eval::colours::kBlack, "ground truth");
  add_path(r.vo_poses, eval::colours::kOrange, "visual odometry");
  add_path(r.slam_poses, eval::colours::kBlue, "delta-GLMB-SLAM");
  if (r.refined_poses) add_path(*r.refined_poses, eval::colours::kGreen, "refined (RFS-ML)");
  plot.save_png(path);
}

}  // namespace

double peak_rss_mib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

namespace {

/// The last frame with measured ground truth (mask empty: the last frame).
std::size_t last_with_ground_truth(const std::vector<char>& mask, std::size_t frames) {
  std::size_t end = frames - 1;
  while (!mask.empty() && end > 0 && !mask[end]) --end;
  return end;
}

/// The record restricted to the frames with ground truth (for the plots and the report, which compare per
/// frame).
RunRecord frames_with_ground_truth(const RunRecord& r) {
  RunRecord kept = r;
  kept.slam_poses.clear();
  kept.vo_poses.clear();
  if (kept.refined_poses) kept.refined_poses->clear();
  kept.ground_truth->clear();
  kept.ground_truth_mask.clear();
  for (std::size_t i = 0; i < r.ground_truth_mask.size(); ++i) {
    if (!r.ground_truth_mask[i]) continue;
    kept.slam_poses.push_back(r.slam_poses[i]);
    kept.vo_poses.push_back(r.vo_poses[i]);
    if (r.refined_poses) kept.refined_poses->push_back((*r.refined_poses)[i]);
    kept.ground_truth->push_back((*r.ground_truth)[i]);
  }
  return kept;
}

}  // namespace

void write_run_outputs(const std::string& out_dir, const RunRecord& r, bool plots) {
  namespace fs = std::filesystem;
  const fs::path dir(out_dir);
  ensure_writable_directory(dir);
  io::write_kitti_poses((dir / "trajectory.txt").string(), r.slam_poses);
  io::write_kitti_poses((dir / "vo_trajectory.txt").string(), r.vo_poses);
  io::write_pcd_map((dir / "map.pcd").string(), r.map);
  if (r.refined_poses) {
    io::write_kitti_poses((dir / "trajectory_refined.txt").string(), *r.refined_poses);
    io::write_pcd_map((dir / "map_refined.pcd").string(), r.refined_map);
  }
  write_text_file_atomically(dir / "config_used.yaml", [&](std::ostream& out) { out << r.effective_config; });
  const bool ground_truth_written =
      write_ground_truth_file(dir, r.ground_truth ? &*r.ground_truth : nullptr, r.ground_truth_mask);

  nlohmann::json j;
  j["dataset"] = r.dataset_name;
  j["algorithm"] = r.algorithm;
  j["particles"] = r.particles;
  j["seed"] = r.seed;
  j["first_frame"] = r.first_frame;
  j["frames"] = r.slam_poses.size();
  j["frames_requested"] = r.frames_requested;
  j["interrupted"] = r.interrupted;
  if (r.interrupted && !r.slam_poses.empty() && r.slam_poses.size() < r.frames_requested)
    j["last_frame_done"] = r.first_frame + r.slam_poses.size() - 1;
  std::string table;
  std::optional<eval::TrajectoryEvaluation> slam_evaluation, vo_evaluation, refined_evaluation;
  // plots and the report compare per frame: with partial ground truth they show the frames that have it
  std::optional<RunRecord> evaluated;
  if (r.ground_truth && !r.ground_truth_mask.empty()) evaluated = frames_with_ground_truth(r);
  const RunRecord& shown = evaluated ? *evaluated : r;
  if (r.ground_truth) {
    const eval::TrajectoryEvaluation& slam = slam_evaluation.emplace(
        eval::evaluate_trajectory_masked(*r.ground_truth, r.slam_poses, r.ground_truth_mask));
    const eval::TrajectoryEvaluation& vo = vo_evaluation.emplace(
        eval::evaluate_trajectory_masked(*r.ground_truth, r.vo_poses, r.ground_truth_mask));
    j["evaluated_frames"] = slam.frames;  // the frames with ground truth
    j["slam"] = eval::to_json(slam);
    j["vo"] = eval::to_json(vo);
    const double path = slam.path_length_m;
    const std::size_t end = last_with_ground_truth(r.ground_truth_mask, r.slam_poses.size());
    auto drift = [&](const PoseList& est) {
      return path > 0 ? 100.0 * (est[end].translation() - (*r.ground_truth)[end].translation()).norm() / path
                      : 0.0;
    };
    j["slam"]["end_point_drift_percent"] = drift(r.slam_poses);
    j["vo"]["end_point_drift_percent"] = drift(r.vo_poses);
    table = "SLAM\n" + eval::format_table(slam) + "\nVO\n" + eval::format_table(vo);
    if (r.refined_poses) {
      const eval::TrajectoryEvaluation& refined = refined_evaluation.emplace(
          eval::evaluate_trajectory_masked(*r.ground_truth, *r.refined_poses, r.ground_truth_mask));
      j["refined"] = eval::to_json(refined);
      j["refined"]["end_point_drift_percent"] = drift(*r.refined_poses);
      table += "\nRefined (RFS-ML)\n" + eval::format_table(refined);
      if (plots)
        eval::write_evaluation_plots((dir / "plots" / "refined").string(), *shown.ground_truth,
                                     *shown.refined_poses, refined, "refined (RFS-ML)");
    }
    if (plots) {
      const RunRecord& e = shown;
      eval::write_evaluation_plots((dir / "plots" / "slam").string(), *e.ground_truth, e.slam_poses, slam,
                                   "delta-GLMB-SLAM");
      eval::write_evaluation_plots((dir / "plots" / "vo").string(), *e.ground_truth, e.vo_poses, vo,
                                   "visual odometry");
    }
  }
  if (plots) {
    ensure_writable_directory(dir / "plots");
    write_map_plot((dir / "plots" / "map_top.png").string(), r);
  }
  const double frames = static_cast<double>(r.slam_poses.size());
  j["timing"] = {{"frontend_ms_median", quantile(r.frontend_ms, 0.5)},
                 {"frontend_ms_p95", quantile(r.frontend_ms, 0.95)},
                 {"vo_ms_median", quantile(r.vo_ms, 0.5)},
                 {"vo_ms_p95", quantile(r.vo_ms, 0.95)},
                 {"backend_ms_median", quantile(r.backend_ms, 0.5)},
                 {"backend_ms_p95", quantile(r.backend_ms, 0.95)},
                 {"backend_ms_mean", summarize(r.backend_ms).mean},
                 {"wall_s", r.wall_s},
                 {"fps", r.wall_s > 0 ? frames / r.wall_s : 0.0},
                 {"peak_rss_mib", peak_rss_mib()}};
  j["map"] = {{"landmarks", r.map.size()}};
  if (r.refined_poses) {
    j["map"]["refined_landmarks"] = r.refined_map.size();
    j["refinement"] = r.refinement;
  }
  if (!r.rectification.empty()) j["rectification"] = r.rectification;
  if (!r.stereo_photometry.empty()) j["stereo_photometry"] = r.stereo_photometry;
  double ess = 0.0, res = 0.0;
  for (double e : r.ess_fraction) ess += e;
  for (bool b : r.resampled) res += b ? 1.0 : 0.0;
  const double steps = static_cast<double>(r.ess_fraction.size());
  j["filter"] = {{"ess_percent", steps > 0 ? 100.0 * ess / steps : 0.0},
                 {"resampling_percent", steps > 0 ? 100.0 * res / steps : 0.0},
                 {"vo_fallback_frames", r.vo_fallbacks},
                 {"missing_frames", r.missing_frames}};
  eval::write_json_file((dir / "metrics.json").string(), j);
  write_run_report((dir / "report.html").string(), shown, j, slam_evaluation ? &*slam_evaluation : nullptr,
                   vo_evaluation ? &*vo_evaluation : nullptr,
                   refined_evaluation ? &*refined_evaluation : nullptr);

  if (r.interrupted && r.slam_poses.size() < r.frames_requested) {
    std::printf("\ninterrupted: %zu of %zu frames done\n", r.slam_poses.size(), r.frames_requested);
  } else if (r.interrupted) {
    std::printf(
        "\ninterrupted during the refinement's final pass: every frame done, the refined trajectory "
        "is the pass's last completed round\n");
  }
  if (!table.empty()) std::printf("\n%s", table.c_str());
  std::printf(
      "\nframes %zu, %.2f fps (frontend median %.1f ms, VO %.1f ms, backend %.1f ms), map %zu landmarks\n",
      r.slam_poses.size(), r.wall_s > 0 ? frames / r.wall_s : 0.0, quantile(r.frontend_ms, 0.5),
      quantile(r.vo_ms, 0.5), quantile(r.backend_ms, 0.5), r.map.size());
  std::printf(
      "outputs in %s:\n  report       %s  (open in a browser)\n  trajectory   %s\n  VO           %s\n"
      "  map          %s\n  metrics      %s\n  plots        %s\n",
      dir.string().c_str(), (dir / "report.html").string().c_str(), (dir / "trajectory.txt").string().c_str(),
      (dir / "vo_trajectory.txt").string().c_str(), (dir / "map.pcd").string().c_str(),
      (dir / "metrics.json").string().c_str(), (dir / "plots").string().c_str());
  if (r.refined_poses) {
    std::printf("  refined      %s, %s\n", (dir / "trajectory_refined.txt").string().c_str(),
                (dir / "map_refined.pcd").string().c_str());
  }
  if (ground_truth_written) std::printf("  ground truth %s\n", (dir / "ground_truth.txt").string().c_str());
}

}  // namespace glmbslam::app
