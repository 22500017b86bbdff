// The stereo final-pass solver (stereo_batch_ml_slam.hpp): its merged pair factor against the per-measurement
// factors it replaces, its frustum candidate search against maybe_in_view, and its solve (one Ceres problem
// re-weighted every EM round) against RfsMlSlam's (a problem rebuilt every round) on a small stereo problem,
// and what its M-step's initial trust region radius does on a long drive.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "backend/mlslam/stereo_batch_ml_slam.hpp"
#include "backend/mlslam/stereo_fill_reducing_ordering.hpp"
#include "core/parallel.hpp"
#include "core/random.hpp"
#include "mlslam_stereo_problem.hpp"
#include "stereo_test_support.hpp"

namespace glmbslam::backend {
namespace {

using test::make_stereo_problem;
using test::max_position_error;
using test::stereo_config;
using test::StereoProblem;

/// r, Jᵀr and JᵀJ of a stereo factor at (pose, landmark), Jacobians in the ambient coordinates.
struct Normal {
  double cost = 0.0;
  Eigen::Matrix<double, 10, 1> g = Eigen::Matrix<double, 10, 1>::Zero();
  Eigen::Matrix<double, 10, 10> H = Eigen::Matrix<double, 10, 10>::Zero();
};

void accumulate(const ceres::CostFunction& f, const double* pose, const double* m, Normal& n) {
  const double* params[] = {pose, m};
  Eigen::Vector3d r;
  Eigen::Matrix<double, 3, kPose3BlockSize, Eigen::RowMajor> Jx;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Jm;
  double* jacobians[] = {Jx.data(), Jm.data()};
  ASSERT_TRUE(f.Evaluate(params, r.data(), jacobians));
  Eigen::Matrix<double, 3, 10> J;
  J << Jx, Jm;
  n.cost += r.squaredNorm();
  n.g += J.transpose() * r;
  n.H += J.transpose() * J;
}

/// Σ_n β_n ‖W (z_n − ẑ)‖² of the per-measurement factors and B ‖W (z̄ − ẑ)‖² of the pair factor: the same
/// gradient and Gauss–Newton matrix, costs differing by Σ_n β_n ‖W (z_n − z̄)‖².
TEST(MlSlamStereoBatch, PairFactorHasTheGradientAndHessianOfItsMeasurements) {
  const StereoMeasurementModel model(test::kitti_calibration(), StereoMeasurementConfig{});
  const Pose3 x = se3_exp((Vector6d() << 0.5, 0.1, 2.0, 0.02, 0.1, -0.03).finished());
  const Eigen::Vector3d m(1.5, -0.5, 14.0);
  const Eigen::Matrix3d W = whitening(model.noise());
  const Eigen::Vector3d zs[] = {model.predict(x, m) + Eigen::Vector3d(0.7, -1.1, 0.4),
                                model.predict(x, m) + Eigen::Vector3d(-1.5, 0.3, -0.9),
                                model.predict(x, m) + Eigen::Vector3d(2.0, 0.8, 1.7)};
  const double betas[] = {0.6, 0.3, 0.05};
  std::vector<double> block(kPose3BlockSize);
  pose3_to_block(x, block.data());
  Normal sum, merged;
  double B = 0.0;
  Eigen::Vector3d Bz = Eigen::Vector3d::Zero();
  for (int n = 0; n < 3; ++n) {
    std::unique_ptr<ceres::CostFunction> f(
        make_stereo_measurement_factor(model.camera(), zs[n], W, betas[n]));
    accumulate(*f, block.data(), m.data(), sum);
    B += betas[n];
    Bz += betas[n] * zs[n];
  }
  const StereoFactorContext context{model.camera(), W};
  StereoPairFactor pair(&context);
  const Eigen::Vector3d z_bar = Bz / B;
  pair.set(z_bar, B);
  accumulate(pair, block.data(), m.data(), merged);
  double constant = 0.0;
  for (int n = 0; n < 3; ++n) constant += betas[n] * (W * (zs[n] - z_bar)).squaredNorm();
  EXPECT_NEAR(merged.cost + constant, sum.cost, 1e-9 * sum.cost);
  EXPECT_LT((merged.g - sum.g).norm(), 1e-9 * sum.g.norm());
  EXPECT_LT((merged.H - sum.H).norm(), 1e-9 * sum.H.norm());
  // B = 0: no cost, no gradient
  pair.set(Eigen::Vector3d::Zero(), 0.0);
  Normal none;
  accumulate(pair, block.data(), m.data(), none);
  EXPECT_EQ(none.cost, 0.0);
  EXPECT_EQ(none.H.norm(), 0.0);
}

/// Every landmark maybe_in_view from a pose lies in its view_box, and the grid's box query returns it.
TEST(MlSlamStereoBatch, FrustumBoxHoldsEveryLandmarkMaybeInView) {
  StereoMeasurementConfig mc;
  mc.min_depth = 1.0;
  mc.max_depth = 40.0;
  const StereoMeasurementModel model(test::kitti_calibration(), mc);
  const SmoothStereoDetection p_D(model, 0.0, 0.0);
  RandomStream rng(4, 2);
  StereoMlSlam::LandmarkList M;
  for (int j = 0; j < 20000; ++j)
    M.emplace_back(rng.uniform(-120.0, 120.0), rng.uniform(-30.0, 30.0), rng.uniform(-120.0, 120.0));
  const LandmarkGrid<3> grid(
      M.size(), [&](std::size_t j) { return M[j]; }, p_D.query_radius() / 8.0);
  std::size_t in_view = 0, boxed = 0;
  for (int k = 0; k < 20; ++k) {
    const Pose3 x =
        se3_exp((Vector6d() << rng.uniform(-20.0, 20.0), rng.uniform(-2.0, 2.0), rng.uniform(-20.0, 20.0),
                 rng.uniform(-0.2, 0.2), rng.uniform(-3.2, 3.2), rng.uniform(-0.2, 0.2))
                    .finished());
    const auto box = p_D.view_box(model, x);
    const std::vector<int> found = grid.in_box(box.first, box.second);
    EXPECT_TRUE(std::is_sorted(found.begin(), found.end()));
    boxed += found.size();
    for (std::size_t j = 0; j < M.size(); ++j) {
      if (!p_D.maybe_in_view(model, x, M[j])) continue;
      ++in_view;
      EXPECT_TRUE((M[j].array() >= box.first.array()).all() && (M[j].array() <= box.second.array()).all());
      EXPECT_TRUE(std::binary_search(found.begin(), found.end(), static_cast<int>(j))) << j;
    }
  }
  EXPECT_GT(in_view, 100u);
  // and far fewer than the cube of the query radius holds
  std::size_t cube = 0;
  for (int k = 0; k < 1; ++k) cube += grid.near(Eigen::Vector3d::Zero(), p_D.query_radius()).size();
  EXPECT_LT(boxed / 20, cube);
}

/// One problem re-weighted every round reaches RfsMlSlam's estimate (a problem rebuilt every round): the same
/// least squares in exact arithmetic, so they differ by rounding (summation order, merged measurements)
/// carried through a few LM iterations per round; 1e-6 m on a 0.2 m correction, 1e-9 relative in l.
TEST(MlSlamStereoBatch, ReusedProblemReachesTheRebuiltProblemsEstimate) {
  for (const char* solver : {"sparse_schur", "sparse_normal_cholesky"}) {
    const StereoProblem p = make_stereo_problem(12, 3);
    MlSlamConfig c = stereo_config();
    c.cardinality_moves = false;
    c.linear_solver = solver;
    c.max_rounds = 40;
    c.solver_iterations = 3;
    c.tolerance = 1e-9;
    const StereoMlSlam rebuilt(p.motion, p.model, c);
    const StereoBatchMlSlam reused(p.motion, p.model, c);
    StereoMlSlam::PoseList x1 = p.odometry, x2 = p.odometry;
    StereoMlSlam::LandmarkList m1 = p.landmarks, m2 = p.landmarks;
    const MlSlamReport r1 = rebuilt.solve(x1, p.controls, p.scans, m1);
    const MlSlamReport r2 = reused.solve(x2, p.controls, p.scans, m2);
    EXPECT_EQ(r1.rounds, r2.rounds) << solver;
    EXPECT_NEAR(r2.initial_log_likelihood, r1.initial_log_likelihood,
                1e-9 * std::abs(r1.initial_log_likelihood));
    EXPECT_NEAR(r2.final_log_likelihood, r1.final_log_likelihood, 1e-9 * std::abs(r1.final_log_likelihood));
    EXPECT_GT(r2.final_log_likelihood, r2.initial_log_likelihood);
    EXPECT_LT(max_position_error(x1, x2), 1e-6) << solver;
    EXPECT_GT(max_position_error(x1, p.odometry), 0.05) << solver;  // the solve moved the poses
    ASSERT_EQ(m1.size(), m2.size());
    double landmark_error = 0.0;
    for (std::size_t j = 0; j < m1.size(); ++j)
      landmark_error = std::max(landmark_error, (m1[j] - m2[j]).norm());
    EXPECT_LT(landmark_error, 1e-5) << solver;
    EXPECT_NEAR(reused.log_likelihood(x2, p.controls, p.scans, m2), r2.final_log_likelihood,
                1e-9 * std::abs(r2.final_log_likelihood));
  }
}

// The one-problem final pass stops as RfsMlSlam does: before a round, with the last round's estimate.
TEST(MlSlamStereoBatch, AStopEndsTheRoundsWithTheLastRoundsEstimate) {
  const StereoProblem p = make_stereo_problem(12, 3);
  MlSlamConfig c = stereo_config();
  c.cardinality_moves = false;
  c.solver_iterations = 3;
  c.tolerance = 0.0;
  MlSlamConfig three = c;
  three.max_rounds = 3;
  StereoBatchMlSlam stopped(p.motion, p.model, c);
  int asked = 0;
  stopped.set_stop([&] { return ++asked > 3; });
  StereoMlSlam::PoseList x1 = p.odometry, x2 = p.odometry;
  StereoMlSlam::LandmarkList m1 = p.landmarks, m2 = p.landmarks;
  const MlSlamReport r1 = stopped.solve(x1, p.controls, p.scans, m1);
  const MlSlamReport r2 = StereoBatchMlSlam(p.motion, p.model, three).solve(x2, p.controls, p.scans, m2);
  EXPECT_TRUE(r1.stopped);
  EXPECT_EQ(r1.rounds, 3);
  EXPECT_EQ(r1.final_log_likelihood, r2.final_log_likelihood);
  EXPECT_GT(r1.final_log_likelihood, r1.initial_log_likelihood);
  EXPECT_EQ(max_position_error(x1, x2), 0.0);
  for (std::size_t j = 0; j < m1.size(); ++j) EXPECT_EQ(m1[j], m2[j]);
}

constexpr int kBentDriveFrames = 400;
constexpr double kBentDriveYawRad = 0.002;  ///< the bend's yaw at the drive's end

/// Max position error after one M-step of one Levenberg–Marquardt iteration from `radius`, on a 400-frame
/// straight drive (1 m per frame, exact controls, noise-free measurements of landmarks on both sides) started
/// from the truth bent by a yaw about the start that grows along the path to 0.002 rad (0.8 m at the end),
/// the landmarks at the truth.
double error_after_one_step_on_a_bent_drive(double radius) {
  const int K = kBentDriveFrames;
  const Se3Motion motion{Se3MotionConfig{}};
  const StereoMeasurementModel model(test::kitti_calibration(), test::stereo_problem_measurement_config());
  const Matrix6d Q = test::stereo_problem_vo_covariance();
  StereoMlSlam::PoseList truth, start;
  StereoMlSlam::ControlList controls;
  for (int k = 0; k < K; ++k) {
    Pose3 x = Pose3::Identity();
    x.translation() = Eigen::Vector3d(0.0, 0.0, k);
    truth.push_back(x);
    RelativePoseControl u;
    u.covariance = Q;
    if (k > 0) u.delta = truth[static_cast<std::size_t>(k) - 1].inverse() * x;
    controls.push_back(u);
    const double yaw = kBentDriveYawRad * k / K;  // about the start: a slow bend of the whole drive
    start.push_back(Pose3(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY())) * x);
  }
  StereoMlSlam::LandmarkList map;
  for (int z = 0; z < K + 40; z += 2)
    for (double side : {-6.0, -3.0, 3.0, 6.0}) map.emplace_back(side, z % 4 == 0 ? -1.0 : 1.0, z + 1.0);
  MlSlamConfig c = test::stereo_config();
  c.linear_solver = "sparse_normal_cholesky";
  c.solver_iterations = 1;
  c.initial_trust_region_radius = radius;
  StereoMStepProblem problem(motion, model, controls, map.size(), c);
  for (std::size_t i = 0; i < truth.size(); ++i)
    for (std::size_t j = 0; j < map.size(); ++j)
      if (model.in_field_of_view(truth[i], map[j]))
        problem.add(i, static_cast<int>(j), model.predict(truth[i], map[j]), 1.0);
  problem.solve(start, map);
  return max_position_error(start, truth);
}

/// Levenberg–Marquardt's damping, 1/radius × diag(JᵀJ), holds back the slow modes of a long trajectory (a
/// bend that builds up over hundreds of poses has eigenvalues of JᵀJ far below its diagonal): one iteration
/// from Ceres' default radius 10⁴ leaves much of the bend, one from 10⁸ (Gauss–Newton's step) removes it.
/// The reason for the final pass's refine.final_trust_region_radius.
TEST(MlSlamStereoBatch, AnUndampedStepStraightensTheSlowBendOfALongDrive) {
  const double last = kBentDriveFrames - 1;
  const double bend =
      last * std::sin(kBentDriveYawRad * last / kBentDriveFrames);  // the start's largest error
  const double damped = error_after_one_step_on_a_bent_drive(1e4);
  const double undamped = error_after_one_step_on_a_bent_drive(1e8);
  EXPECT_GT(damped, 0.25 * bend);   // 0.32 m of 0.80 m left
  EXPECT_LT(undamped, 0.1 * bend);  // 0.034 m left (the rotation's nonlinearity)
}

TEST(MlSlamStereoBatch, SameInputSameOutputAtAnyThreadCount) {
  const StereoProblem p = make_stereo_problem(12, 8);
  MlSlamConfig c = stereo_config();
  c.cardinality_moves = false;
  test::expect_same_output_at_1_and_2_threads(StereoBatchMlSlam(p.motion, p.model, c), p);
}

/// Nested dissection orders every node once; on a path it eliminates a middle node (a separator) last, not an
/// end as the natural order does.
TEST(MlSlamStereoBatch, NestedDissectionOrdersEveryNodeOnce) {
  const int n = 101;
  std::vector<std::vector<int>> path(n);
  for (int i = 1; i < n; ++i) path[i].push_back(i - 1), path[i - 1].push_back(i);
  std::vector<int> order = nested_dissection_order(path);
  ASSERT_EQ(order.size(), static_cast<std::size_t>(n));
  const int last = order.back();
  EXPECT_GT(last, 10);
  EXPECT_LT(last, n - 11);
  std::sort(order.begin(), order.end());
  for (int i = 0; i < n; ++i) EXPECT_EQ(order[static_cast<std::size_t>(i)], i);
  EXPECT_TRUE(nested_dissection_order({}).empty());
}

TEST(MlSlamStereoBatch, RefusesWhatOnlyRfsMlSlamDoes) {
  const StereoProblem p = make_stereo_problem(3, 1);
  MlSlamConfig c = stereo_config();
  c.cardinality_moves = true;
  EXPECT_FALSE(StereoBatchMlSlam::supports(c));
  EXPECT_THROW(StereoBatchMlSlam(p.motion, p.model, c), std::invalid_argument);
  c.cardinality_moves = false;
  c.association = "nearest_neighbour";
  EXPECT_FALSE(StereoBatchMlSlam::supports(c));
}

}  // namespace
}  // namespace glmbslam::backend
