#include "eval/report.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/atomic_file.hpp"

namespace glmbslam::eval {
namespace {

/// A number, or null when not finite (JSON has no NaN).
nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json rpe_fields(const RpeResult& r) {
  nlohmann::json j;
  if (r.by_distance) {
    j["delta_m"] = r.delta;
  } else {
    j["delta_frames"] = static_cast<int>(r.delta);
  }
  j["pairs"] = r.pairs;
  j["trans_rmse_m"] = number(r.trans_rmse_m);
  j["trans_mean_m"] = number(r.trans_mean_m);
  j["rot_rmse_deg"] = number(r.rot_rmse_deg);
  j["rot_mean_deg"] = number(r.rot_mean_deg);
  return j;
}

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

void kitti_table(std::string& out, const char* name, const KittiResult& k) {
  char line[256];
  std::snprintf(line, sizeof(line), "%-12s t_rel %s %%   r_rel %s deg/100m   segments %d\n", name,
                fmt("%.6f", k.t_rel_percent).c_str(), fmt("%.6f", k.r_rel_deg_per_100m).c_str(), k.segments);
  out += line;
  for (const auto& l : k.per_length) {
    if (l.segments == 0) continue;  // the path is shorter than this length: nothing to show
    std::snprintf(line, sizeof(line), "  %6.0f m   t_rel %10s %%   r_rel %10s deg/100m   segments %d\n",
                  l.length_m, fmt("%.4f", l.t_rel_percent).c_str(), fmt("%.4f", l.r_rel_deg_per_100m).c_str(),
                  l.segments);
    out += line;
  }
}

}  // namespace

TrajectoryEvaluation evaluate_trajectory(const PoseList& gt, const PoseList& est,
                                         const EvaluationOptions& options) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("evaluate_trajectory: ground truth has " + std::to_string(gt.size()) +
                                " poses, estimate has " + std::to_string(est.size()));
  }
  if (gt.empty()) throw std::invalid_argument("evaluate_trajectory: empty trajectories");
  TrajectoryEvaluation e;
  e.frames = static_cast<int>(gt.size());
  for (size_t i = 1; i < gt.size(); ++i)
    e.path_length_m += (gt[i].translation() - gt[i - 1].translation()).norm();
  e.kitti = evaluate_kitti(gt, est, options.kitti_lengths, options.kitti_step_frames);
  e.kitti_short = evaluate_kitti(gt, est, options.kitti_short_lengths, options.kitti_step_frames);
  e.ate = evaluate_ate(gt, est);
  for (int d : options.rpe_frame_deltas) e.rpe_frames.push_back(evaluate_rpe_frames(gt, est, d));
  for (double d : options.rpe_distance_deltas_m) e.rpe_distances.push_back(evaluate_rpe_distance(gt, est, d));
  return e;
}

nlohmann::json to_json(const KittiResult& k) {
  nlohmann::json j;
  j["t_rel_percent"] = number(k.t_rel_percent);
  j["r_rel_deg_per_100m"] = number(k.r_rel_deg_per_100m);
  j["segments"] = k.segments;
  nlohmann::json per = nlohmann::json::array();
  for (const auto& l : k.per_length) {
    per.push_back({{"length_m", l.length_m},
                   {"segments", l.segments},
                   {"t_rel_percent", number(l.t_rel_percent)},
                   {"r_rel_deg_per_100m", number(l.r_rel_deg_per_100m)}});
  }
  j["per_length"] = per;
  return j;
}

nlohmann::json to_json(const AteResult& a) {
  return {{"poses", a.poses},
          {"se3_rmse_m", number(a.se3_rmse_m)},
          {"sim3_rmse_m", number(a.sim3_rmse_m)},
          {"sim3_scale", number(a.sim3_scale)}};
}

nlohmann::json to_json(const TrajectoryEvaluation& e) {
  nlohmann::json j;
  j["frames"] = e.frames;
  j["path_length_m"] = e.path_length_m;
  j["kitti"] = to_json(e.kitti);
  j["kitti_short"] = to_json(e.kitti_short);
  j["ate"] = to_json(e.ate);
  nlohmann::json rpe = nlohmann::json::object();
  if (!e.rpe_frames.empty()) rpe = rpe_fields(e.rpe_frames.front());
  nlohmann::json by_frames = nlohmann::json::array();
  for (const auto& r : e.rpe_frames) by_frames.push_back(rpe_fields(r));
  nlohmann::json by_distance = nlohmann::json::array();
  for (const auto& r : e.rpe_distances) by_distance.push_back(rpe_fields(r));
  rpe["by_frame_delta"] = by_frames;
  rpe["by_distance"] = by_distance;
  j["rpe"] = rpe;
  return j;
}

std::string format_table(const TrajectoryEvaluation& e) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof(line), "frames %d, ground-truth path %.1f m\n", e.frames, e.path_length_m);
  out += line;
  kitti_table(out, "KITTI", e.kitti);
  kitti_table(out, "KITTI short", e.kitti_short);
  std::snprintf(line, sizeof(line), "ATE         SE(3) RMSE %s m   Sim(3) RMSE %s m   Sim(3) scale %s\n",
                fmt("%.4f", e.ate.se3_rmse_m).c_str(), fmt("%.4f", e.ate.sim3_rmse_m).c_str(),
                fmt("%.5f", e.ate.sim3_scale).c_str());
  out += line;
  auto rpe_line = [&](const RpeResult& r) {
    const std::string delta = r.by_distance ? fmt("%.0f m", r.delta) : fmt("%.0f frames", r.delta);
    std::snprintf(line, sizeof(line),
                  "RPE %-10s trans RMSE %s m (mean %s)   rot RMSE %s deg (mean %s)   pairs %d\n",
                  delta.c_str(), fmt("%.4f", r.trans_rmse_m).c_str(), fmt("%.4f", r.trans_mean_m).c_str(),
                  fmt("%.4f", r.rot_rmse_deg).c_str(), fmt("%.4f", r.rot_mean_deg).c_str(), r.pairs);
    out += line;
  };
  for (const auto& r : e.rpe_frames) rpe_line(r);
  for (const auto& r : e.rpe_distances) rpe_line(r);
  return out;
}

void write_json_file(const std::string& path, const nlohmann::json& j) {
  write_text_file_atomically(path, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

}  // namespace glmbslam::eval
