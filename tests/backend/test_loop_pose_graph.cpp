// backend/mlslam/loop_pose_graph.hpp: a drifted loop bent back by one loop constraint, a consistent graph
// left where it is, a wrong loop rejected by the χ² gate.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "backend/mlslam/loop_pose_graph.hpp"

namespace glmbslam::backend {
namespace {

/// A circle of n poses (radius 20 m) in the x–z plane, the camera looking along the tangent.
PoseVector circle(std::size_t n) {
  PoseVector poses;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(n);
    Pose3 T = Pose3::Identity();
    T.linear() = Eigen::AngleAxisd(-a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(20.0 * std::sin(a), 0.0, 20.0 * (1.0 - std::cos(a)));
    poses.push_back(T);
  }
  return poses;
}

/// The same motions, each with a small heading bias: the drift of an odometry.
PoseVector drifted(const PoseVector& truth, double yaw_bias) {
  PoseVector out{truth[0]};
  Pose3 bias = Pose3::Identity();
  bias.linear() = Eigen::AngleAxisd(yaw_bias, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (std::size_t k = 1; k < truth.size(); ++k)
    out.push_back(out.back() * (truth[k - 1].inverse() * truth[k]) * bias);
  return out;
}

Matrix6dVector odometry_covariance(std::size_t n) {
  Matrix6d Q = Matrix6d::Zero();
  Q.diagonal() << 1e-4, 1e-4, 1e-4, 1e-6, 1e-6, 1e-6;
  return Matrix6dVector(n, Q);
}

LoopConstraint loop_between(const PoseVector& truth, std::size_t i, std::size_t j) {
  LoopConstraint c;
  c.i = i;
  c.j = j;
  c.relative = truth[i].inverse() * truth[j];
  c.W = Matrix6d::Zero();
  c.W.diagonal() << 100.0, 100.0, 100.0, 1000.0, 1000.0, 1000.0;  // σ 1 cm / 0.001 rad
  return c;
}

double position_error(const PoseVector& a, const PoseVector& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    worst = std::max(worst, (a[k].translation() - b[k].translation()).norm());
  return worst;
}

TEST(LoopPoseGraph, OneLoopConstraintTakesTheDriftOut) {
  const PoseVector truth = circle(60);
  PoseVector poses = drifted(truth, 0.002);
  const double before = position_error(poses, truth);
  ASSERT_GT(before, 1.0);  // the odometry ends metres away from where it started
  const LoopPoseGraphReport r =
      optimise_loop_pose_graph(poses, odometry_covariance(poses.size()), {loop_between(truth, 0, 59)});
  EXPECT_EQ(r.loops_used, 1);
  EXPECT_EQ(r.loops_rejected, 0);
  EXPECT_LT(r.final_cost, r.initial_cost);
  // the loop's end is where the constraint puts it (σ 1 cm, the odometry 100× softer); a heading bias bends
  // every step, so the middle of the loop keeps part of its error: the worst error falls, it does not vanish
  EXPECT_LT((poses[59].translation() - truth[59].translation()).norm(), 0.05);
  EXPECT_LT(position_error(poses, truth), 0.5 * before);
  EXPECT_EQ(poses[0].matrix(), truth[0].matrix());  // the first pose is held
}

TEST(LoopPoseGraph, TheCorrectionGoesToTheUncertainStep) {
  // all the drift in one step (a 1.5 m jump) whose covariance says so (10⁶× the others): the loop puts
  // every pose back where it was, up to the share the stiff steps and the loop take (variances of order
  // 0.05 m² at the loop's 20–40 m lever arms against 100 m² for the jump: under 1e-3 of it)
  const PoseVector truth = circle(40);
  PoseVector poses{truth[0]};
  Pose3 jump = Pose3::Identity();
  jump.translation() = Eigen::Vector3d(1.0, 0.0, 1.1);
  for (std::size_t k = 1; k < truth.size(); ++k)
    poses.push_back(poses.back() * (k == 15 ? jump : Pose3::Identity()) *
                    (truth[k - 1].inverse() * truth[k]));
  Matrix6dVector Q = odometry_covariance(truth.size());
  Q[15] *= 1e6;
  ASSERT_GT(position_error(poses, truth), 1.0);
  optimise_loop_pose_graph(poses, Q, {loop_between(truth, 0, 39)});
  EXPECT_LT(position_error(poses, truth), 0.01);
}

TEST(LoopPoseGraph, AConsistentGraphStaysWhereItIs) {
  const PoseVector truth = circle(30);
  PoseVector poses = truth;
  optimise_loop_pose_graph(poses, odometry_covariance(poses.size()), {loop_between(truth, 2, 27)});
  EXPECT_LT(position_error(poses, truth), 1e-6);
}

TEST(LoopPoseGraph, AWrongLoopIsRejectedAndTheRightOneKept) {
  const PoseVector truth = circle(60);
  const PoseVector start = drifted(truth, 0.002);
  LoopConstraint wrong = loop_between(truth, 10, 50);
  wrong.relative.translation() += Eigen::Vector3d(8.0, 0.0, -5.0);  // a place that only looked the same
  PoseVector with_wrong = start, right_only = start;
  const Matrix6dVector Q = odometry_covariance(start.size());
  const LoopPoseGraphReport r = optimise_loop_pose_graph(with_wrong, Q, {loop_between(truth, 0, 59), wrong});
  EXPECT_EQ(r.loops_rejected, 1);
  EXPECT_EQ(r.loops_used, 1);
  optimise_loop_pose_graph(right_only, Q, {loop_between(truth, 0, 59)});
  EXPECT_LT(position_error(with_wrong, right_only), 1e-9);
}

TEST(LoopPoseGraph, NoLoopsLeavesThePosesAndBadInputThrows) {
  const PoseVector truth = circle(10);
  PoseVector poses = drifted(truth, 0.01);
  const PoseVector before = poses;
  optimise_loop_pose_graph(poses, odometry_covariance(poses.size()), {});
  EXPECT_EQ(position_error(poses, before), 0.0);
  EXPECT_THROW(optimise_loop_pose_graph(poses, odometry_covariance(3), {}), std::invalid_argument);
  EXPECT_THROW(
      optimise_loop_pose_graph(poses, odometry_covariance(poses.size()), {loop_between(truth, 0, 12)}),
      std::invalid_argument);
}

}  // namespace
}  // namespace glmbslam::backend
