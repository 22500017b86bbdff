// RFS-ML-SLAM on paper 004's 1D problem (backend/mlslam/line_ml_slam.hpp): the motion factor against the
// motion model, the initial pose search of the standalone solve, and convergence from the odometry where
// dead reckoning leaves the landmarks outside every gate.
#include <cmath>

#include <gtest/gtest.h>

#include "backend/mlslam/line_ml_slam.hpp"
#include "core/error.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {
namespace {

LinePose at(double v) {
  return LinePose::Constant(v);
}

/// A robot on a line, 0.06 m per step, five landmarks ahead, exact-noise data from `seed`.
struct LineProblem {
  std::vector<double> truth;
  LineMlSlam::ControlList u;
  std::vector<LineMlSlam::MeasurementSet> Z;
  explicit LineProblem(std::uint64_t seed, int steps = 40) {
    RandomStream rng(seed, 7);
    const std::vector<double> landmarks{3.4, 4.6, 5.5, 6.7, 7.5};
    for (int k = 0; k < steps; ++k) {
      truth.push_back(0.06 * k);
      u.push_back(at(k == 0 ? 0.0 : 0.06 + 0.1 * rng.normal()));
      Z.emplace_back();
      for (double m : landmarks) {
        const double z = m - truth.back();
        if (z >= 0.5 && z <= 6.0 && rng.uniform() < 0.9) Z.back().push_back(at(z + 0.01 * rng.normal()));
      }
    }
  }
};

LineMlSlam make_slam(int search) {
  MlSlamConfig c;
  c.incremental_steps = 1;
  c.initial_pose_search = search;
  LineSensorConfig s;
  s.clutter_rate = 0.055;
  return LineMlSlam(LineMotion(), LineMeasurementModel(s), c);
}

TEST(LineMlSlam, MotionFactorIsTheWhitenedOdometryResidual) {
  const LineMotion motion;
  const std::unique_ptr<ceres::CostFunction> f(
      LineMlSlamParts::motion_factor(motion, at(0.06), at(10.0), at(0.0), 1.0));
  const double prev = 1.0, cur = 1.2;
  const double* params[] = {&prev, &cur};
  double r = 0.0, j0 = 0.0, j1 = 0.0;
  double* jacobians[] = {&j0, &j1};
  ASSERT_TRUE(f->Evaluate(params, &r, jacobians));
  EXPECT_NEAR(r, 10.0 * (1.2 - 1.0 - 0.06), 1e-12);
  EXPECT_DOUBLE_EQ(j0, -10.0);
  EXPECT_DOUBLE_EQ(j1, 10.0);
  // ‖r‖² = −2 log g − log(2π q) at the model's q (1e-2, w = 10)
  EXPECT_NEAR(-0.5 * r * r - 0.5 * std::log(2.0 * M_PI * 1e-2),
              motion.log_density(at(cur), at(prev), at(0.06)), 1e-12);
}

TEST(LineMlSlam, InitialPoseSearchFindsThePoseTheScanSees) {
  // the robot moved 0.26 m where the odometry says 0.06 m (2σ): the known landmarks are 20 σ_z away
  const LineMlSlam::LandmarkList map{at(3.0), at(4.0), at(5.5)};
  LineMlSlam::MeasurementSet Z;
  for (const auto& m : map) Z.push_back(at(m(0) - 0.26));
  EXPECT_DOUBLE_EQ(make_slam(0).initial_pose(at(0.0), at(0.06), Z, map)(0), 0.06);
  const double found = make_slam(61).initial_pose(at(0.0), at(0.06), Z, map)(0);
  EXPECT_NEAR(found, 0.26, 0.005);  // grid spacing 0.6 m / 60 = 0.01 m
  // nothing to match: dead reckoning
  EXPECT_DOUBLE_EQ(make_slam(61).initial_pose(at(0.0), at(0.06), {}, map)(0), 0.06);
}

TEST(LineMlSlam, ConvergesFromTheOdometryOnlyWithTheInitialPoseSearch) {
  for (std::uint64_t seed = 0; seed < 3; ++seed) {
    const LineProblem p(seed);
    auto rmse = [&](int search, std::size_t* landmarks) {
      LineMlSlam::PoseList x;
      LineMlSlam::LandmarkList m;
      make_slam(search).solve_from_odometry(at(0.0), p.u, p.Z, x, m);
      double se = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) se += std::pow(x[k](0) - p.truth[k], 2);
      *landmarks = m.size();
      return std::sqrt(se / static_cast<double>(x.size()));
    };
    std::size_t with = 0, without = 0;
    EXPECT_LT(rmse(61, &with), 0.02) << "seed " << seed;  // σ_z = 0.01 m, σ_u = 0.1 m per step
    EXPECT_EQ(with, 5u) << "seed " << seed;
    // dead-reckoned starts: the landmarks fall outside the gate, EM never sees them
    EXPECT_GT(rmse(0, &without), 0.05) << "seed " << seed;
  }
}

TEST(LineMlSlam, InitialPoseSearchOutOfRangeIsAConfigError) {
  MlSlamConfig c;
  c.initial_pose_search = -1;
  EXPECT_THROW(validate_mlslam_config(c), ConfigError);
  c.initial_pose_search = 5000;
  EXPECT_THROW(validate_mlslam_config(c), ConfigError);
}

}  // namespace
}  // namespace glmbslam::backend
