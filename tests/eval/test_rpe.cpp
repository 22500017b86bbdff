#include <cmath>

#include <gtest/gtest.h>

#include "eval/rpe.hpp"

namespace glmbslam::eval {
namespace {

PoseList line(int frames, double step) {
  PoseList poses;
  for (int i = 0; i < frames; ++i) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(0.0, 0.0, step * i);
    poses.push_back(T);
  }
  return poses;
}

TEST(Rpe, FrameDeltaHandComputed) {
  // Estimate moves 1.1 m per frame instead of 1 m: at Δ frames the relative translation error is 0.1·Δ m.
  const PoseList gt = line(50, 1.0);
  const PoseList est = line(50, 1.1);
  for (int delta : {1, 5}) {
    const RpeResult r = evaluate_rpe_frames(gt, est, delta);
    EXPECT_EQ(r.pairs, 50 - delta);
    EXPECT_NEAR(r.trans_rmse_m, 0.1 * delta, 1e-12);
    EXPECT_NEAR(r.trans_mean_m, 0.1 * delta, 1e-12);
    EXPECT_NEAR(r.rot_rmse_deg, 0.0, 1e-6);
  }
}

TEST(Rpe, RotationErrorAndRmseVersusMean) {
  // One frame has a wrong heading of 2°: with Δ = 1 the pairs touching it have 2° rotation error, others 0.
  const PoseList gt = line(11, 1.0);
  PoseList est = gt;
  est[5].linear() = Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const RpeResult r = evaluate_rpe_frames(gt, est, 1);
  EXPECT_EQ(r.pairs, 10);
  EXPECT_NEAR(r.rot_mean_deg, 2.0 * 2.0 / 10.0, 1e-6);
  EXPECT_NEAR(r.rot_rmse_deg, std::sqrt(2.0 * 4.0 / 10.0), 1e-6);
}

TEST(Rpe, RotationsWrittenWithSixDigitsAgainstThemselvesHaveNoError) {
  // A turning path written as KITTI pose files hold it (six significant digits, so RᵀR ≠ I by ~1e-7): the
  // estimate equal to the ground truth has no rotation error (acos of the trace gave ~0.01° here).
  PoseList gt;
  for (int i = 0; i < 30; ++i) {
    Pose3 T = Pose3::Identity();
    T.linear() = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d(0.1, 1.0, 0.05).normalized()).toRotationMatrix();
    T.linear() = (T.linear() * 1e6).array().round().matrix() / 1e6;
    T.translation() = Eigen::Vector3d(0.3 * i, 0.0, 1.0 * i);
    gt.push_back(T);
  }
  const RpeResult r = evaluate_rpe_frames(gt, gt, 1);
  EXPECT_LT(r.rot_rmse_deg, 1e-12);
  // and an error of 1e-7 rad (below acos's ~1.5e-8 resolution by an order only) comes out exact
  PoseList est = gt;
  est[10].linear() = est[10].linear() * Eigen::AngleAxisd(1e-7, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const RpeResult one = evaluate_rpe_frames(gt, est, 1);
  EXPECT_NEAR(one.rot_mean_deg, 2.0 * 1e-7 * 180.0 / M_PI / 29.0, 1e-13);
}

TEST(Rpe, DistanceDelta) {
  // 1 m per frame: a 10 m delta pairs frame i with i + 11 (first frame strictly beyond 10 m).
  const PoseList gt = line(40, 1.0);
  const PoseList est = line(40, 1.1);
  const RpeResult r = evaluate_rpe_distance(gt, est, 10.0);
  EXPECT_TRUE(r.by_distance);
  EXPECT_EQ(r.pairs, 40 - 11);
  EXPECT_NEAR(r.trans_rmse_m, 1.1, 1e-9);
  const RpeResult none = evaluate_rpe_distance(gt, est, 100.0);
  EXPECT_EQ(none.pairs, 0);
  EXPECT_TRUE(std::isnan(none.trans_rmse_m));
}

TEST(Rpe, BadArguments) {
  EXPECT_THROW(evaluate_rpe_frames(line(3, 1), line(4, 1), 1), std::invalid_argument);
  EXPECT_THROW(evaluate_rpe_frames(line(3, 1), line(3, 1), 0), std::invalid_argument);
  EXPECT_THROW(evaluate_rpe_distance(line(3, 1), line(3, 1), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace glmbslam::eval
