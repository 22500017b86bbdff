#include "app/pipeline/loop_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "core/lie.hpp"
#include "core/random.hpp"

namespace glmbslam::app {

namespace {

using Descriptor = std::array<std::uint8_t, 32>;

int hamming(const Descriptor& a, const Descriptor& b) {
  int d = 0;
  for (std::size_t w = 0; w < 4; ++w) {
    std::uint64_t x = 0, y = 0;
    std::memcpy(&x, a.data() + 8 * w, 8);
    std::memcpy(&y, b.data() + 8 * w, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

/// (index in a, index in b) of b's points whose best descriptor in a passes the distance and ratio tests.
std::vector<std::pair<int, int>> match_descriptors(const LoopKeyframe& a, const LoopKeyframe& b,
                                                   const LoopDetectorOptions& o) {
  std::vector<std::pair<int, int>> matches;
  for (std::size_t j = 0; j < b.descriptors.size(); ++j) {
    int best = 257, second = 257, best_i = -1;
    for (std::size_t i = 0; i < a.descriptors.size(); ++i) {
      const int d = hamming(a.descriptors[i], b.descriptors[j]);
      if (d < best) {
        second = best;
        best = d;
        best_i = static_cast<int>(i);
      } else if (d < second) {
        second = d;
      }
    }
    if (best_i >= 0 && best <= o.max_hamming && best < o.ratio * second)
      matches.emplace_back(best_i, static_cast<int>(j));
  }
  return matches;
}

/// Whether T_ab carries b's point j onto a's measurement i within inlier_px in u_L, v and u_R.
bool reprojects(const Pose3& T_ab, const LoopKeyframe& a, int i, const LoopKeyframe& b, int j,
                const StereoCamera& camera, double inlier_px) {
  const Eigen::Vector3d p = T_ab * b.points[static_cast<std::size_t>(j)];
  if (p.z() < 0.1) return false;
  const Eigen::Vector3d z_a = camera.project(a.points[static_cast<std::size_t>(i)]);  // a's measurement
  return (camera.project(p) - z_a).cwiseAbs().maxCoeff() <= inlier_px;
}

std::vector<std::pair<int, int>> inliers_of(const Pose3& T_ab,
                                            const std::vector<std::pair<int, int>>& matches,
                                            const LoopKeyframe& a, const LoopKeyframe& b,
                                            const StereoCamera& camera, double inlier_px) {
  std::vector<std::pair<int, int>> in;
  for (const auto& [i, j] : matches)
    if (reprojects(T_ab, a, i, b, j, camera, inlier_px)) in.emplace_back(i, j);
  return in;
}

/// Umeyama's rigid fit (no scale) of b's points onto a's for the given pairs.
Pose3 rigid_fit(const std::vector<std::pair<int, int>>& pairs, const LoopKeyframe& a, const LoopKeyframe& b) {
  Eigen::Matrix3Xd src(3, static_cast<Eigen::Index>(pairs.size())), dst(3, src.cols());
  for (std::size_t n = 0; n < pairs.size(); ++n) {
    src.col(static_cast<Eigen::Index>(n)) = b.points[static_cast<std::size_t>(pairs[n].second)];
    dst.col(static_cast<Eigen::Index>(n)) = a.points[static_cast<std::size_t>(pairs[n].first)];
  }
  return Pose3(Eigen::umeyama(src, dst, false));
}

/// Gauss–Newton on Σ ‖π(T X_b) − z_a‖² over T ← T Exp(δ) (∂(T Exp(δ) X)/∂δ = R [I | −[X]×]).
Pose3 refine_reprojection(Pose3 T, const std::vector<std::pair<int, int>>& pairs, const LoopKeyframe& a,
                          const LoopKeyframe& b, const StereoCamera& camera) {
  for (int iteration = 0; iteration < 10; ++iteration) {
    Matrix6d H = Matrix6d::Zero();
    Vector6d g = Vector6d::Zero();
    for (const auto& [i, j] : pairs) {
      const Eigen::Vector3d& X = b.points[static_cast<std::size_t>(j)];
      const Eigen::Vector3d p = T * X;
      if (p.z() < 0.1) continue;
      Eigen::Matrix<double, 3, 6> dp;
      dp.leftCols<3>() = T.linear();
      dp.rightCols<3>() = -T.linear() * skew(X);
      const Eigen::Matrix<double, 3, 6> J = camera.project_jacobian(p) * dp;
      const Eigen::Vector3d r = camera.project(p) - camera.project(a.points[static_cast<std::size_t>(i)]);
      H += J.transpose() * J;
      g += J.transpose() * r;
    }
    const Vector6d delta = -H.ldlt().solve(g);
    if (!delta.allFinite()) break;
    T = se3_plus(T, delta);
    if (delta.norm() < 1e-9) break;
  }
  return T;
}

}  // namespace

std::optional<KeyframeMatch> match_keyframes(const LoopKeyframe& a, const LoopKeyframe& b,
                                             const StereoCamera& camera, const LoopDetectorOptions& o,
                                             std::uint64_t seed) {
  const auto matches = match_descriptors(a, b, o);
  if (matches.size() < std::max<std::size_t>(o.min_inliers, 3)) return std::nullopt;
  RandomStream rng(seed, 0x100F);
  std::vector<std::pair<int, int>> best;
  std::vector<std::pair<int, int>> sample(3);
  for (int it = 0; it < o.ransac_iterations; ++it) {
    const std::size_t s0 = rng.index(matches.size());
    std::size_t s1 = rng.index(matches.size()), s2 = rng.index(matches.size());
    if (s1 == s0 || s2 == s0 || s2 == s1) continue;
    sample = {matches[s0], matches[s1], matches[s2]};
    const Pose3 T = rigid_fit(sample, a, b);
    if (!T.matrix().allFinite()) continue;
    auto in = inliers_of(T, matches, a, b, camera, o.inlier_px);
    if (in.size() > best.size()) best = std::move(in);
  }
  if (best.size() < o.min_inliers) return std::nullopt;
  Pose3 T = refine_reprojection(rigid_fit(best, a, b), best, a, b, camera);
  best = inliers_of(T, matches, a, b, camera, o.inlier_px);
  if (best.size() < o.min_inliers) return std::nullopt;
  T = refine_reprojection(T, best, a, b, camera);
  return KeyframeMatch{T, best.size()};
}

LoopDetector::LoopDetector(const LoopDetectorOptions& options, const StereoCalibration& calibration)
    : options_(options), camera_(calibration) {}

void LoopDetector::add_frame(std::size_t k, const frontend::StereoMeasurementList& measurements) {
  if (options_.keyframe_every == 0 || k % options_.keyframe_every != 0) return;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < measurements.size(); ++i)
    if (measurements[i].point.z() > 0.0 && measurements[i].point.z() <= options_.max_depth_m)
      order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return measurements[x].response > measurements[y].response;
  });
  if (order.size() > options_.max_points) order.resize(options_.max_points);
  LoopKeyframe kf;
  kf.k = k;
  for (std::size_t i : order) {
    kf.points.push_back(measurements[i].point);
    kf.descriptors.push_back(measurements[i].descriptor);
  }
  keyframes_.push_back(std::move(kf));
}

std::vector<backend::LoopConstraint> LoopDetector::detect(const PoseList& trajectory) const {
  std::vector<double> path(trajectory.size(), 0.0);  // distance travelled up to each frame
  for (std::size_t k = 1; k < trajectory.size(); ++k)
    path[k] = path[k - 1] + (trajectory[k].translation() - trajectory[k - 1].translation()).norm();
  const double cos_max = std::cos(options_.max_view_angle_deg * M_PI / 180.0);
  Matrix6d W = Matrix6d::Zero();
  W.diagonal() << Eigen::Vector3d::Constant(1.0 / options_.sigma_translation_m),
      Eigen::Vector3d::Constant(1.0 / options_.sigma_rotation_rad);
  std::vector<backend::LoopConstraint> loops;
  std::vector<std::pair<double, std::size_t>> candidates;
  for (std::size_t jb = 0; jb < keyframes_.size(); ++jb) {
    const LoopKeyframe& b = keyframes_[jb];
    if (b.k >= trajectory.size() || b.points.size() < options_.min_inliers) continue;
    const Pose3& xb = trajectory[b.k];
    candidates.clear();
    for (std::size_t ja = 0; ja < jb; ++ja) {
      const LoopKeyframe& a = keyframes_[ja];
      if (a.k + options_.min_gap_frames > b.k || a.points.size() < options_.min_inliers) continue;
      const Pose3& xa = trajectory[a.k];
      const double radius =
          std::min(options_.max_search_radius_m,
                   options_.search_radius_m + options_.search_radius_per_m * (path[b.k] - path[a.k]));
      const double distance = (xa.translation() - xb.translation()).norm();
      if (distance > radius || xa.linear().col(2).dot(xb.linear().col(2)) < cos_max) continue;
      candidates.emplace_back(distance, ja);
    }
    std::sort(candidates.begin(), candidates.end());
    if (candidates.size() > options_.candidates) candidates.resize(options_.candidates);
    for (const auto& [distance, ja] : candidates) {
      const LoopKeyframe& a = keyframes_[ja];
      const auto m = match_keyframes(a, b, camera_, options_, a.k * 1000003ULL + b.k);
      if (!m) continue;
      loops.push_back(backend::LoopConstraint{a.k, b.k, m->T_ab, W});
      break;
    }
  }
  return loops;
}

}  // namespace glmbslam::app
