// Stereo RFS-ML-SLAM (paper 004 with SE(3) poses and (u_L, v, u_R) measurements): the factors against the
// models they stand for and finite differences, convergence from a perturbed start on a small synthetic
// stereo problem with known geometry, and the same output at 1 and 2 threads.
#include <gtest/gtest.h>

#include <ceres/gradient_checker.h>

#include "backend/mlslam/m_step_linear_solver.hpp"
#include "backend/mlslam/stereo_ml_slam.hpp"
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

Pose3 pose(const Vector6d& xi) {
  return se3_exp(xi);
}

std::vector<double> block_of(const Pose3& T) {
  std::vector<double> b(kPose3BlockSize);
  pose3_to_block(T, b.data());
  return b;
}

/// The Jacobians of `f` (times the manifolds' PlusJacobian) against central differences along the manifolds.
void expect_jacobians_match_finite_differences(const ceres::CostFunction& f,
                                               const std::vector<const ceres::Manifold*>& manifolds,
                                               std::vector<std::vector<double>> blocks) {
  ceres::NumericDiffOptions options;
  ceres::GradientChecker checker(&f, &manifolds, options);
  std::vector<double*> parameters;
  for (auto& b : blocks) parameters.push_back(b.data());
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters.data(), 1e-6, &results)) << results.error_log;
}

TEST(MlSlamStereoFactors, RelativePoseResidualIsTheWhitenedSe3Difference) {
  const Pose3 a = pose((Vector6d() << 0.3, -0.2, 1.0, 0.05, -0.1, 0.2).finished());
  const Pose3 u = pose((Vector6d() << 0.02, 0.01, 0.9, 0.01, 0.03, -0.02).finished());
  const Pose3 b = a * u * se3_exp((Vector6d() << 0.05, -0.03, 0.1, 0.02, -0.01, 0.03).finished());
  Matrix6d W = Matrix6d::Identity();
  W(0, 1) = 0.3;
  W(5, 5) = 4.0;
  std::unique_ptr<ceres::CostFunction> f(make_relative_pose_factor(u, W));
  auto pa = block_of(a), pb = block_of(b);
  const double* params[] = {pa.data(), pb.data()};
  Vector6d r;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  const Vector6d expected = W * se3_minus(b, a * u);  // Se3Motion::local(x_i, f(x_{i−1}, u))
  EXPECT_LT((r - expected).norm(), 1e-9);
  // and 0 at the prediction
  auto pc = block_of(a * u);
  const double* at_prediction[] = {pa.data(), pc.data()};
  ASSERT_TRUE(f->Evaluate(at_prediction, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-9);
}

TEST(MlSlamStereoFactors, StereoResidualIsTheWeightedReprojectionError) {
  const StereoMeasurementModel model(test::kitti_calibration(), StereoMeasurementConfig{});
  const Pose3 x = pose((Vector6d() << 0.5, 0.1, 2.0, 0.02, 0.1, -0.03).finished());
  Eigen::Vector3d m(1.5, -0.5, 14.0);
  const Eigen::Vector3d z = model.predict(x, m) + Eigen::Vector3d(0.7, -1.1, 0.4);
  const Eigen::Matrix3d W = Eigen::Matrix3d::Identity() * 0.5;
  std::unique_ptr<ceres::CostFunction> f(make_stereo_measurement_factor(model.camera(), z, W, 0.64));
  auto px = block_of(x);
  const double* params[] = {px.data(), m.data()};
  Eigen::Vector3d r;
  ASSERT_TRUE(f->Evaluate(params, r.data(), nullptr));
  EXPECT_LT((r - 0.8 * W * (z - model.predict(x, m))).norm(), 1e-9);
}

TEST(MlSlamStereoFactors, JacobiansMatchFiniteDifferencesOnTheManifold) {
  const StereoMeasurementModel model(test::kitti_calibration(), StereoMeasurementConfig{});
  const Pose3CeresManifold se3;
  const ceres::EuclideanManifold<3> r3;
  const Pose3 a = pose((Vector6d() << 0.3, -0.2, 1.0, 0.05, -0.1, 0.2).finished());
  const Pose3 u = pose((Vector6d() << 0.02, 0.01, 0.9, 0.01, 0.03, -0.02).finished());
  const Pose3 b = a * u * se3_exp((Vector6d() << 0.05, -0.03, 0.1, 0.02, -0.01, 0.03).finished());
  std::unique_ptr<ceres::CostFunction> motion(make_relative_pose_factor(u, Matrix6d::Identity() * 10.0));
  expect_jacobians_match_finite_differences(*motion, {&se3, &se3}, {block_of(a), block_of(b)});
  // a motion error below 1e-3 rad: the small-angle branch of the logarithm
  const Pose3 c = a * u * se3_exp((Vector6d() << 0.01, -0.02, 0.03, 2e-4, -1e-4, 3e-4).finished());
  expect_jacobians_match_finite_differences(*motion, {&se3, &se3}, {block_of(a), block_of(c)});
  const Eigen::Vector3d m = a * Eigen::Vector3d(1.5, -0.5, 14.0);
  std::unique_ptr<ceres::CostFunction> stereo(
      make_stereo_measurement_factor(model.camera(), model.predict(a, m), Eigen::Matrix3d::Identity(), 0.5));
  expect_jacobians_match_finite_differences(*stereo, {&se3, &r3},
                                            {block_of(a), std::vector<double>(m.data(), m.data() + 3)});
}

/// J · PlusJacobian: the Jacobian on the manifold's tangent (what Ceres solves with).
Eigen::MatrixXd tangent_jacobian(const double* ambient, int rows, int cols, const ceres::Manifold& manifold,
                                 const double* x) {
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      ambient, rows, cols);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> plus(manifold.AmbientSize(),
                                                                              manifold.TangentSize());
  manifold.PlusJacobian(x, plus.data());
  return J * plus;
}

TEST(MlSlamStereoFactors, AnalyticStereoJacobiansEqualTheAutomaticOnes) {
  const StereoMeasurementModel model(test::kitti_calibration(), StereoMeasurementConfig{});
  const Pose3CeresManifold se3;
  RandomStream rng(7, 0);
  Eigen::Matrix3d W;
  W << 2.0, 0.0, 0.0, 0.3, 1.5, 0.0, -0.2, 0.1, 1.0;
  for (int trial = 0; trial < 20; ++trial) {
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi(k) = rng.normal(0.0, k < 3 ? 5.0 : 0.5);
    const Pose3 x = pose(xi);
    const Eigen::Vector3d m =
        x * Eigen::Vector3d(rng.normal(0.0, 4.0), rng.normal(0.0, 2.0), 5.0 + 30.0 * rng.uniform());
    const Eigen::Vector3d z =
        model.predict(x, m) +
        Eigen::Vector3d(rng.normal(0.0, 2.0), rng.normal(0.0, 2.0), rng.normal(0.0, 2.0));
    std::unique_ptr<ceres::CostFunction> analytic(make_stereo_measurement_factor(model.camera(), z, W, 0.7));
    std::unique_ptr<ceres::CostFunction> automatic(
        make_stereo_measurement_factor_autodiff(model.camera(), z, W, 0.7));
    auto px = block_of(x);
    const double* params[] = {px.data(), m.data()};
    Eigen::Vector3d ra, rb;
    double Ja_x[21], Ja_m[9], Jb_x[21], Jb_m[9];
    double* Ja[] = {Ja_x, Ja_m};
    double* Jb[] = {Jb_x, Jb_m};
    ASSERT_TRUE(analytic->Evaluate(params, ra.data(), Ja));
    ASSERT_TRUE(automatic->Evaluate(params, rb.data(), Jb));
    EXPECT_LT((ra - rb).norm(), 1e-9 * (1.0 + rb.norm()));
    const Eigen::MatrixXd Ta = tangent_jacobian(Ja_x, 3, 7, se3, px.data());
    const Eigen::MatrixXd Tb = tangent_jacobian(Jb_x, 3, 7, se3, px.data());
    EXPECT_LT((Ta - Tb).norm(), 1e-9 * (1.0 + Tb.norm())) << "trial " << trial;
    EXPECT_LT((Eigen::Map<Eigen::Matrix3d>(Ja_m) - Eigen::Map<Eigen::Matrix3d>(Jb_m)).norm(),
              1e-9 * (1.0 + Eigen::Map<Eigen::Matrix3d>(Jb_m).norm()));
  }
}

TEST(MlSlamStereoFactors, SmoothDetectionIsHalfAtTheBorderAndFullInside) {
  StereoMeasurementConfig c;
  c.p_detect_inside = 0.8;
  c.min_depth = 1.0;
  c.max_depth = 40.0;
  const StereoMeasurementModel model(test::kitti_calibration(), c);
  const SmoothStereoDetection p_D(model, 0.5, 2.0);
  const Pose3 x = Pose3::Identity();
  auto at = [&](const Eigen::Vector3d& m) { return p_D(model, x, m, model.predict(x, m)); };
  EXPECT_NEAR(at({0.0, 0.0, 20.0}), 0.8, 1e-6);
  EXPECT_NEAR(at({0.0, 0.0, 40.0}), 0.4, 1e-3);  // the depth border
  EXPECT_EQ(at({0.0, 0.0, -5.0}), 0.0);          // behind the camera
  const StereoCamera& cam = model.camera();      // the right image border u_L = W (v and u_R inside)
  EXPECT_NEAR(at({(model.image_width() - cam.cx) * 20.0 / cam.fx, 0.0, 20.0}), 0.4, 1e-3);
  const double r = p_D.query_radius();
  EXPECT_LT(at({r * 0.7, 0.0, r * 0.7}), 1e-6);  // beyond the query radius: never detected
}

TEST(MlSlamStereoSolver, ConvergesFromAPerturbedStart) {
  const StereoProblem p = make_stereo_problem(10, 5);
  const StereoMlSlam slam(p.motion, p.model, stereo_config());
  StereoMlSlam::PoseList x = p.odometry;
  RandomStream rng(9, 1);
  for (std::size_t k = 1; k < x.size(); ++k)
    x[k] = se3_plus(x[k], (Vector6d() << rng.normal(0.0, 0.1), rng.normal(0.0, 0.1), rng.normal(0.0, 0.2),
                           0.0, rng.normal(0.0, 0.002), 0.0)
                              .finished());
  StereoMlSlam::LandmarkList m = p.landmarks;
  for (auto& l : m) l += rng.gaussian<3>(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity() * 1e-3);
  const double start_error = max_position_error(x, p.truth);
  const double l_truth = slam.log_likelihood(p.truth, p.controls, p.scans, p.landmarks);
  const MlSlamReport r = slam.solve(x, p.controls, p.scans, m);
  EXPECT_GT(r.final_log_likelihood, r.initial_log_likelihood);
  for (std::size_t i = 1; i < r.log_likelihood_per_round.size(); ++i)
    EXPECT_GE(r.log_likelihood_per_round[i], r.log_likelihood_per_round[i - 1]);
  EXPECT_GT(r.final_log_likelihood, l_truth);  // the truth is near, not at, the maximum
  EXPECT_GT(start_error, 0.2);
  EXPECT_LT(max_position_error(x, p.truth), 0.05);
  EXPECT_LT(max_position_error(x, p.truth), max_position_error(p.odometry, p.truth));
}

/// The M-step's linear solvers (Schur elimination of the landmarks, factorised densely or sparsely or solved
/// by conjugate gradients, and the plain normal equations) solve the same least-squares problem: the same
/// optimum, cardinality moves off.
TEST(MlSlamStereoSolver, LinearSolversReachTheSameOptimum) {
  const StereoProblem p = make_stereo_problem(12, 3);
  std::vector<StereoMlSlam::PoseList> poses;
  std::vector<double> l;
  for (const char* solver :
       {"sparse_normal_cholesky", "dense_schur", "sparse_schur", "iterative_schur", "auto"}) {
    MlSlamConfig c = stereo_config();
    c.cardinality_moves = false;
    c.linear_solver = solver;
    c.max_rounds = 40;
    c.tolerance = 1e-9;
    const StereoMlSlam slam(p.motion, p.model, c);
    StereoMlSlam::PoseList x = p.odometry;
    StereoMlSlam::LandmarkList m = p.landmarks;
    l.push_back(slam.solve(x, p.controls, p.scans, m).final_log_likelihood);
    poses.push_back(x);
  }
  for (std::size_t v = 1; v < poses.size(); ++v) {
    EXPECT_NEAR(l[v], l[0], 1e-6 * std::abs(l[0])) << v;           // EM stops within its tolerance
    EXPECT_LT(max_position_error(poses[v], poses[0]), 5e-4) << v;  // the start is 0.2 m off
  }
  EXPECT_GT(l[0], StereoMlSlam(p.motion, p.model, stereo_config())
                      .log_likelihood(p.odometry, p.controls, p.scans, p.landmarks));
}

/// "auto" takes the dense Schur complement for a window's few poses, the sparse one up to 200 poses and the
/// normal equations beyond; a named solver is taken at any size.
TEST(MlSlamStereoSolver, AutoPicksTheLinearSolverByPoseCount) {
  MlSlamConfig c;
  c.linear_solver = "auto";
  EXPECT_EQ(m_step_linear_solver(c, 10), ceres::DENSE_SCHUR);
  EXPECT_EQ(m_step_linear_solver(c, MlSlamConfig::kAutoDensePoses), ceres::DENSE_SCHUR);
  EXPECT_EQ(m_step_linear_solver(c, MlSlamConfig::kAutoDensePoses + 1), ceres::SPARSE_SCHUR);
  EXPECT_EQ(m_step_linear_solver(c, MlSlamConfig::kAutoSchurPoses), ceres::SPARSE_SCHUR);
  EXPECT_EQ(m_step_linear_solver(c, MlSlamConfig::kAutoSchurPoses + 1), ceres::SPARSE_NORMAL_CHOLESKY);
  c.linear_solver = "sparse_schur";
  EXPECT_EQ(m_step_linear_solver(c, 10), ceres::SPARSE_SCHUR);
  c.linear_solver = "dense_schur";
  EXPECT_EQ(m_step_linear_solver(c, 5000), ceres::DENSE_SCHUR);
}

TEST(MlSlamStereoSolver, SameInputSameOutputAtAnyThreadCount) {
  const StereoProblem p = make_stereo_problem(12, 8);
  test::expect_same_output_at_1_and_2_threads(StereoMlSlam(p.motion, p.model, stereo_config()), p);
}

}  // namespace
}  // namespace glmbslam::backend
