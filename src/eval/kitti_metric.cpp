#include "eval/kitti_metric.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace glmbslam::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// The devkit's lastFrameFromSegmentLength: first frame whose distance exceeds dist[first] + len, or -1.
int last_frame_from_segment_length(const std::vector<float>& dist, int first_frame, float len) {
  const float target = dist[static_cast<size_t>(first_frame)] + len;
  // dist is non-decreasing, so the first frame beyond the target can be found by binary search.
  const auto it = std::upper_bound(dist.begin() + first_frame, dist.end(), target);
  return it == dist.end() ? -1 : static_cast<int>(it - dist.begin());
}

/// The devkit's rotationError (float arithmetic).
float rotation_error(const Eigen::Matrix4d& e) {
  const float a = static_cast<float>(e(0, 0));
  const float b = static_cast<float>(e(1, 1));
  const float c = static_cast<float>(e(2, 2));
  const float d = 0.5f * (a + b + c - 1.0f);
  return std::acos(std::max(std::min(d, 1.0f), -1.0f));
}

/// The devkit's translationError.
float translation_error(const Eigen::Matrix4d& e) {
  const float dx = static_cast<float>(e(0, 3));
  const float dy = static_cast<float>(e(1, 3));
  const float dz = static_cast<float>(e(2, 3));
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

std::vector<double> kitti_standard_lengths() {
  return {100, 200, 300, 400, 500, 600, 700, 800};
}

std::vector<double> kitti_short_lengths() {
  return {10, 20, 30, 40, 50, 60, 70, 80};
}

std::vector<float> trajectory_distances(const PoseList& poses) {
  std::vector<float> dist;
  dist.reserve(poses.size());
  if (poses.empty()) return dist;
  dist.push_back(0.0f);
  for (size_t i = 1; i < poses.size(); ++i) {
    const Eigen::Vector3d d = poses[i - 1].translation() - poses[i].translation();
    const float dx = static_cast<float>(d.x());
    const float dy = static_cast<float>(d.y());
    const float dz = static_cast<float>(d.z());
    dist.push_back(dist[i - 1] + std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return dist;
}

KittiResult evaluate_kitti(const PoseList& gt, const PoseList& est, const std::vector<double>& lengths,
                           int step_size) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("evaluate_kitti: ground truth has " + std::to_string(gt.size()) +
                                " poses, estimate has " + std::to_string(est.size()));
  }
  if (step_size < 1) throw std::invalid_argument("evaluate_kitti: step_size must be ≥ 1");
  const int n = static_cast<int>(gt.size());
  const std::vector<float> dist = trajectory_distances(gt);

  KittiResult result;
  std::vector<double> t_sum(lengths.size(), 0.0);
  std::vector<double> r_sum(lengths.size(), 0.0);
  std::vector<int> count(lengths.size(), 0);
  for (int first = 0; first < n; first += step_size) {
    // Inverses are general 4×4 inverses, as the devkit's Matrix::inv (poses are not re-orthonormalised).
    const Eigen::Matrix4d gt_first_inv = gt[static_cast<size_t>(first)].matrix().inverse();
    const Eigen::Matrix4d est_first_inv = est[static_cast<size_t>(first)].matrix().inverse();
    for (size_t k = 0; k < lengths.size(); ++k) {
      const float len = static_cast<float>(lengths[k]);
      const int last = last_frame_from_segment_length(dist, first, len);
      if (last < 0) continue;
      const Eigen::Matrix4d delta_gt = gt_first_inv * gt[static_cast<size_t>(last)].matrix();
      const Eigen::Matrix4d delta_est = est_first_inv * est[static_cast<size_t>(last)].matrix();
      const Eigen::Matrix4d error = delta_est.inverse() * delta_gt;
      KittiSegmentError s;
      s.first_frame = first;
      s.last_frame = last;
      s.length_m = lengths[k];
      s.r_err = static_cast<float>(rotation_error(error) / len);
      s.t_err = static_cast<float>(translation_error(error) / len);
      result.segment_errors.push_back(s);
      t_sum[k] += s.t_err;
      r_sum[k] += s.r_err;
      ++count[k];
    }
  }

  const double nan = std::numeric_limits<double>::quiet_NaN();
  double t_total = 0.0;
  double r_total = 0.0;
  for (const auto& s : result.segment_errors) {
    t_total += s.t_err;
    r_total += s.r_err;
  }
  result.segments = static_cast<int>(result.segment_errors.size());
  result.t_rel_percent = result.segments > 0 ? 100.0 * t_total / result.segments : nan;
  result.r_rel_deg_per_100m = result.segments > 0 ? 100.0 * kRadToDeg * r_total / result.segments : nan;
  for (size_t k = 0; k < lengths.size(); ++k) {
    KittiLengthResult l;
    l.length_m = lengths[k];
    l.segments = count[k];
    l.t_rel_percent = count[k] > 0 ? 100.0 * t_sum[k] / count[k] : nan;
    l.r_rel_deg_per_100m = count[k] > 0 ? 100.0 * kRadToDeg * r_sum[k] / count[k] : nan;
    result.per_length.push_back(l);
  }
  return result;
}

}  // namespace glmbslam::eval
