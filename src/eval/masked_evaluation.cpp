#include "eval/masked_evaluation.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace glmbslam::eval {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

PoseList slice(const PoseList& poses, std::size_t first, std::size_t last) {
  return PoseList(poses.begin() + static_cast<long>(first), poses.begin() + static_cast<long>(last));
}

/// The segments of every stretch in one result; means recomputed over the pooled segments.
KittiResult pooled_kitti(const PoseList& gt, const PoseList& est,
                         const std::vector<std::pair<std::size_t, std::size_t>>& stretches,
                         const std::vector<double>& lengths, int step) {
  KittiResult result;
  for (const auto& [first, last] : stretches) {
    const KittiResult part = evaluate_kitti(slice(gt, first, last), slice(est, first, last), lengths, step);
    for (KittiSegmentError s : part.segment_errors) {
      s.first_frame += static_cast<int>(first);
      s.last_frame += static_cast<int>(first);
      result.segment_errors.push_back(s);
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto means = [&](double length, int& count, double& t, double& r) {
    double ts = 0.0, rs = 0.0;
    count = 0;
    for (const auto& s : result.segment_errors) {
      if (length > 0.0 && s.length_m != length) continue;
      ts += s.t_err;
      rs += s.r_err;
      ++count;
    }
    t = count > 0 ? 100.0 * ts / count : nan;
    r = count > 0 ? 100.0 * kRadToDeg * rs / count : nan;
  };
  means(0.0, result.segments, result.t_rel_percent, result.r_rel_deg_per_100m);
  for (double length : lengths) {
    KittiLengthResult l;
    l.length_m = length;
    means(length, l.segments, l.t_rel_percent, l.r_rel_deg_per_100m);
    result.per_length.push_back(l);
  }
  return result;
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> ground_truth_stretches(const std::vector<char>& mask) {
  std::vector<std::pair<std::size_t, std::size_t>> stretches;
  for (std::size_t i = 0; i < mask.size();) {
    if (!mask[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < mask.size() && mask[j]) ++j;
    stretches.emplace_back(i, j);
    i = j;
  }
  return stretches;
}

TrajectoryEvaluation evaluate_trajectory_masked(const PoseList& gt, const PoseList& est,
                                                const std::vector<char>& mask,
                                                const EvaluationOptions& options) {
  if (mask.empty()) return evaluate_trajectory(gt, est, options);
  if (mask.size() != gt.size() || gt.size() != est.size()) {
    throw std::invalid_argument("evaluate_trajectory_masked: ground truth has " + std::to_string(gt.size()) +
                                " poses, estimate " + std::to_string(est.size()) + ", mask " +
                                std::to_string(mask.size()));
  }
  PoseList gt_kept, est_kept;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    gt_kept.push_back(gt[i]);
    est_kept.push_back(est[i]);
  }
  if (gt_kept.empty()) throw std::invalid_argument("evaluate_trajectory_masked: no frame has ground truth");
  if (gt_kept.size() == gt.size()) return evaluate_trajectory(gt, est, options);
  // ATE, RPE and the path length over the kept frames (an RPE pair or a path step may span a gap)
  TrajectoryEvaluation e = evaluate_trajectory(gt_kept, est_kept, options);
  const auto stretches = ground_truth_stretches(mask);
  e.kitti = pooled_kitti(gt, est, stretches, options.kitti_lengths, options.kitti_step_frames);
  e.kitti_short = pooled_kitti(gt, est, stretches, options.kitti_short_lengths, options.kitti_step_frames);
  return e;
}

}  // namespace glmbslam::eval
