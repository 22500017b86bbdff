#include "eval/eval_plots.hpp"

#include <filesystem>

#include "core/atomic_file.hpp"
#include "eval/line_plot.hpp"

namespace glmbslam::eval {

std::vector<std::string> write_evaluation_plots(const std::string& dir, const PoseList& gt,
                                                const PoseList& est, const TrajectoryEvaluation& evaluation,
                                                const std::string& est_label) {
  ensure_writable_directory(dir);
  const std::filesystem::path d(dir);
  std::vector<std::string> written;

  {
    LinePlot p("Trajectory (top view)", "x [m]", "z [m]");
    p.set_equal_aspect(true);
    auto add = [&](const PoseList& poses, Rgb colour, const std::string& label) {
      std::vector<double> x, z;
      x.reserve(poses.size());
      z.reserve(poses.size());
      for (const auto& T : poses) {
        x.push_back(T.translation().x());
        z.push_back(T.translation().z());
      }
      p.add_series(x, z, colour, label);
    };
    add(gt, colours::kBlack, "ground truth");
    add(est, colours::kRed, est_label);
    if (!gt.empty()) {
      p.add_series({gt.front().translation().x()}, {gt.front().translation().z()}, colours::kBlue, "start",
                   SeriesStyle::kMarkers, 3);
    }
    written.push_back((d / "trajectory_top.png").string());
    p.save_png(written.back());
  }

  {
    const bool use_short = evaluation.kitti.segments == 0 && evaluation.kitti_short.segments > 0;
    const KittiResult& k = use_short ? evaluation.kitti_short : evaluation.kitti;
    const std::string suffix = use_short ? " (short lengths)" : "";
    std::vector<double> len, t, r;
    for (const auto& l : k.per_length) {
      len.push_back(l.length_m);
      t.push_back(l.t_rel_percent);
      r.push_back(l.r_rel_deg_per_100m);
    }
    LinePlot pt("Translation error vs segment length" + suffix, "segment length [m]",
                "translation error [%]");
    pt.set_include_zero_y(true);
    pt.add_series(len, t, colours::kBlue, est_label, SeriesStyle::kLineMarkers);
    written.push_back((d / "kitti_t_err.png").string());
    pt.save_png(written.back());
    LinePlot pr("Rotation error vs segment length" + suffix, "segment length [m]",
                "rotation error [deg/100 m]");
    pr.set_include_zero_y(true);
    pr.add_series(len, r, colours::kBlue, est_label, SeriesStyle::kLineMarkers);
    written.push_back((d / "kitti_r_err.png").string());
    pr.save_png(written.back());
  }

  {
    std::vector<double> dist(gt.size(), 0.0);
    for (size_t i = 1; i < gt.size(); ++i)
      dist[i] = dist[i - 1] + (gt[i].translation() - gt[i - 1].translation()).norm();
    LinePlot p("Absolute trajectory error along the path", "distance along ground truth [m]",
               "position error [m]");
    p.set_include_zero_y(true);
    p.add_series(dist, evaluation.ate.se3_errors_m, colours::kRed, "SE(3) aligned");
    if (!evaluation.ate.sim3_errors_m.empty())
      p.add_series(dist, evaluation.ate.sim3_errors_m, colours::kBlue, "Sim(3) aligned");
    written.push_back((d / "ate_error.png").string());
    p.save_png(written.back());
  }
  return written;
}

}  // namespace glmbslam::eval
