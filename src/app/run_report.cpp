#include "app/run_report.hpp"

#include "eval/html_report.hpp"
#include "eval/report_figures.hpp"

namespace glmbslam::app {
namespace {

namespace colours = eval::report_colours;
using json = nlohmann::json;

void add_metrics(eval::HtmlReport& report, const json& metrics) {
  report.add_section("Metrics", "metrics.json of this run, flattened.");
  report.add_table("", {"key", "value"}, eval::metrics_rows(metrics));
}

/// The headline table: one row per evaluated path.
void add_summary(eval::HtmlReport& report, const std::vector<eval::ReportEvaluation>& evaluations) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& e : evaluations) {
    const eval::TrajectoryEvaluation& v = *e.evaluation;
    const bool standard = v.kitti.segments > 0;
    const eval::KittiResult& k = standard ? v.kitti : v.kitti_short;
    rows.push_back({e.name, eval::format_number(k.t_rel_percent, 4),
                    eval::format_number(k.r_rel_deg_per_100m, 4), standard ? "100–800 m" : "10–80 m",
                    eval::format_number(v.ate.se3_rmse_m, 4), eval::format_number(v.path_length_m, 5)});
  }
  report.add_table(
      "Against the ground truth",
      {"path", "t_rel [%]", "r_rel [deg/100 m]", "segment lengths", "ATE SE(3) [m]", "path length [m]"},
      rows);
}

}  // namespace

void write_run_report(const std::string& path, const RunRecord& r, const json& metrics,
                      const eval::TrajectoryEvaluation* slam, const eval::TrajectoryEvaluation* vo,
                      const eval::TrajectoryEvaluation* refined) {
  eval::HtmlReport report("glmbslam run: " + r.dataset_name,
                          r.algorithm + ", " + std::to_string(r.particles) + " particle(s), seed " +
                              std::to_string(r.seed) + ", frames " + std::to_string(r.first_frame) + "–" +
                              std::to_string(r.first_frame + r.slam_poses.size() - 1));
  std::vector<eval::ReportEvaluation> evaluations;
  if (slam) evaluations.push_back({"δ-GLMB-SLAM", slam, colours::kSlam});
  if (vo) evaluations.push_back({"visual odometry", vo, colours::kVo});
  if (refined) evaluations.push_back({"refined (RFS-ML)", refined, colours::kRefined});
  if (!evaluations.empty()) add_summary(report, evaluations);

  report.add_section(
      "Map and camera paths",
      "Landmarks of the final MAP estimate (map.pcd), coloured by existence probability; hover "
      "shows the δ-GLMB label (birth frame << 12 | index). Paths relative to the first frame.");
  std::vector<eval::ReportPath> paths;
  if (r.ground_truth) paths.push_back({"ground truth", &*r.ground_truth, colours::kGroundTruth});
  paths.push_back({"visual odometry", &r.vo_poses, colours::kVo});
  paths.push_back({"δ-GLMB-SLAM", &r.slam_poses, colours::kSlam});
  if (r.refined_poses) paths.push_back({"refined", &*r.refined_poses, colours::kRefined});
  eval::add_map_and_paths(report, r.map, paths);

  if (r.ground_truth && !evaluations.empty()) {
    report.add_section("Trajectory errors", "KITTI odometry metric (official devkit) and ATE.");
    eval::add_trajectory_errors(report, *r.ground_truth, evaluations);
  }

  if (!r.ess_fraction.empty() || !r.tracks.empty()) {
    report.add_section("Filter over time");
    if (!r.ess_fraction.empty()) {
      std::vector<double> ess;
      for (double e : r.ess_fraction) ess.push_back(100.0 * e);
      report.add_plot(
          "Effective sample size (before resampling)",
          json::array({eval::line_trace("ESS / N", eval::index_axis(ess.size(), 1.0), ess, colours::kSlam)}),
          eval::axes_layout("frame (from the first processed)", "ESS [% of N]"), 320);
    }
    if (!r.tracks.empty()) {
      const std::vector<double> tracks(r.tracks.begin(), r.tracks.end());
      report.add_plot("Landmarks over time (tracks of the best particle)",
                      json::array({eval::line_trace("landmarks", eval::index_axis(tracks.size()), tracks,
                                                    colours::kPurple)}),
                      eval::axes_layout("frame (from the first processed)", "landmarks"), 320);
    }
  }
  add_metrics(report, metrics);
  report.add_section("Configuration");
  report.add_text("config_used.yaml (the effective configuration)", r.effective_config, true);
  report.write(path);
}

void write_vo_report(const std::string& path, const VoReportInput& in, const json& metrics) {
  eval::HtmlReport report("glmbslam vo: " + in.dataset,
                          "stereo visual odometry, frames " + std::to_string(in.first_frame) + "–" +
                              std::to_string(in.first_frame + in.poses->size() - 1));
  std::vector<eval::ReportEvaluation> evaluations;
  if (in.evaluation) {
    evaluations.push_back({"visual odometry", in.evaluation, colours::kVo});
    add_summary(report, evaluations);
  }
  report.add_section("Camera paths", "Relative to the first frame of the range.");
  std::vector<eval::ReportPath> paths;
  if (*in.ground_truth) paths.push_back({"ground truth", &**in.ground_truth, colours::kGroundTruth});
  paths.push_back({"visual odometry", in.poses, colours::kVo});
  eval::add_map_and_paths(report, {}, paths);
  if (in.evaluation) {
    report.add_section("Trajectory errors", "KITTI odometry metric (official devkit) and ATE.");
    eval::add_trajectory_errors(report, **in.ground_truth, evaluations);
  }
  report.add_section("Tracking over time");
  const std::vector<double> frames =
      eval::index_axis(in.measurements.size(), static_cast<double>(in.first_frame));
  report.add_plot(
      "Stereo measurements, matches to the previous frame and PnP inliers",
      json::array({eval::line_trace("stereo measurements", frames, in.measurements, colours::kSlam),
                   eval::line_trace("matches", frames, in.matches, colours::kVo),
                   eval::line_trace("inliers", frames, in.inliers, colours::kRefined)}),
      eval::axes_layout("frame", "count"), 350);
  add_metrics(report, metrics);
  report.add_section("Configuration");
  report.add_text("frontend configuration", in.config.empty() ? "(built-in defaults)" : in.config, true);
  report.write(path);
}

}  // namespace glmbslam::app
