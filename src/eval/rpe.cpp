#include "eval/rpe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/lie.hpp"

namespace glmbslam::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

struct Accumulator {
  int n = 0;
  double t_sum = 0.0, t_sq = 0.0, r_sum = 0.0, r_sq = 0.0;

  void add(const Pose3& gt_i, const Pose3& gt_j, const Pose3& est_i, const Pose3& est_j) {
    const Pose3 e = (gt_i.inverse() * gt_j).inverse() * (est_i.inverse() * est_j);
    const double t = e.translation().norm();
    const double r = rotation_angle(e.linear()) * kRadToDeg;
    ++n;
    t_sum += t;
    t_sq += t * t;
    r_sum += r;
    r_sq += r * r;
  }

  void finish(RpeResult& out) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.pairs = n;
    out.trans_rmse_m = n > 0 ? std::sqrt(t_sq / n) : nan;
    out.trans_mean_m = n > 0 ? t_sum / n : nan;
    out.rot_rmse_deg = n > 0 ? std::sqrt(r_sq / n) : nan;
    out.rot_mean_deg = n > 0 ? r_sum / n : nan;
  }
};

void check_sizes(const PoseList& gt, const PoseList& est) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("RPE: ground truth has " + std::to_string(gt.size()) +
                                " poses, estimate has " + std::to_string(est.size()));
  }
}

}  // namespace

RpeResult evaluate_rpe_frames(const PoseList& gt, const PoseList& est, int delta_frames) {
  check_sizes(gt, est);
  if (delta_frames < 1) throw std::invalid_argument("RPE: frame delta must be ≥ 1");
  Accumulator acc;
  for (size_t i = 0; i + static_cast<size_t>(delta_frames) < gt.size(); ++i) {
    const size_t j = i + static_cast<size_t>(delta_frames);
    acc.add(gt[i], gt[j], est[i], est[j]);
  }
  RpeResult r;
  r.by_distance = false;
  r.delta = delta_frames;
  acc.finish(r);
  return r;
}

RpeResult evaluate_rpe_distance(const PoseList& gt, const PoseList& est, double delta_m) {
  check_sizes(gt, est);
  if (!(delta_m > 0.0)) throw std::invalid_argument("RPE: distance delta must be > 0");
  std::vector<double> dist(gt.size(), 0.0);
  for (size_t i = 1; i < gt.size(); ++i) {
    dist[i] = dist[i - 1] + (gt[i].translation() - gt[i - 1].translation()).norm();
  }
  Accumulator acc;
  for (size_t i = 0; i < gt.size(); ++i) {
    const auto it =
        std::upper_bound(dist.begin() + static_cast<std::ptrdiff_t>(i), dist.end(), dist[i] + delta_m);
    if (it == dist.end()) break;  // later starts cannot reach further either
    const size_t j = static_cast<size_t>(it - dist.begin());
    acc.add(gt[i], gt[j], est[i], est[j]);
  }
  RpeResult r;
  r.by_distance = true;
  r.delta = delta_m;
  acc.finish(r);
  return r;
}

}  // namespace glmbslam::eval
