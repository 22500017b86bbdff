#pragma once
// A small synthetic stereo RFS-ML-SLAM problem with known geometry, shared by the stereo solver tests
// (test_mlslam_stereo.cpp, test_mlslam_stereo_batch.cpp).
#include <algorithm>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "backend/mlslam/stereo_ml_slam.hpp"
#include "core/parallel.hpp"
#include "core/random.hpp"
#include "stereo_test_support.hpp"

namespace glmbslam::backend::test {

/// The stereo sensor of the test problems: 1 px noise, depths 1–40 m, p_D 0.8, 2 clutter points per frame.
inline StereoMeasurementConfig stereo_problem_measurement_config() {
  StereoMeasurementConfig mc;
  mc.pixel_sigma = 1.0;
  mc.min_depth = 1.0;
  mc.max_depth = 40.0;
  mc.p_detect_inside = 0.8;
  mc.clutter_rate = 2.0;
  return mc;
}

/// The VO control covariance Q of the test problems (σ 2, 2, 4 cm and 0.003 rad per frame).
inline Matrix6d stereo_problem_vo_covariance() {
  Matrix6d Q = Matrix6d::Zero();
  Q.diagonal() << 0.02, 0.02, 0.04, 0.003, 0.003, 0.003;
  return Q.cwiseProduct(Q);
}

/// A small stereo problem with known geometry: the camera moves ~1 m per frame along z with a slow turn, past
/// landmarks spread in a box ahead; VO controls with noise drawn from their Q; measurement sets with misses
/// and Poisson clutter.
struct StereoProblem {
  Se3Motion motion;
  StereoMeasurementModel model;
  StereoMlSlam::PoseList truth, odometry;
  StereoMlSlam::LandmarkList landmarks;
  StereoMlSlam::ControlList controls;
  std::vector<StereoMlSlam::MeasurementSet> scans;
};

inline StereoProblem make_stereo_problem(int K, std::uint64_t seed) {
  const StereoMeasurementConfig mc = stereo_problem_measurement_config();
  StereoProblem p{Se3Motion(Se3MotionConfig{}),
                  StereoMeasurementModel(test::kitti_calibration(), mc),
                  {},
                  {},
                  {},
                  {},
                  {}};
  RandomStream rng(seed, 11);
  for (int j = 0; j < 60; ++j)
    p.landmarks.emplace_back(rng.uniform(-12.0, 12.0), rng.uniform(-3.0, 2.0), rng.uniform(6.0, 35.0));
  const Matrix6d Q = stereo_problem_vo_covariance();
  const Pose3 step = se3_exp((Vector6d() << 0.0, 0.0, 1.0, 0.0, 0.01, 0.0).finished());
  p.truth.push_back(Pose3::Identity());
  p.odometry.push_back(Pose3::Identity());
  p.controls.push_back(RelativePoseControl{});
  for (int k = 1; k < K; ++k) {
    p.truth.push_back(p.truth.back() * step);
    RelativePoseControl u;
    u.delta = step * se3_exp(rng.gaussian<6>(Vector6d::Zero(), Q));
    u.covariance = Q;
    p.controls.push_back(u);
    p.odometry.push_back(p.odometry.back() * u.delta);
  }
  const StereoCamera& cam = p.model.camera();
  for (const auto& x : p.truth) {
    StereoMlSlam::MeasurementSet Z;
    for (const auto& m : p.landmarks) {
      if (!p.model.in_field_of_view(x, m) || rng.uniform() >= mc.p_detect_inside) continue;
      Z.push_back(p.model.predict(x, m) + rng.gaussian<3>(Eigen::Vector3d::Zero(), p.model.noise()));
    }
    const int clutter = static_cast<int>(rng.index(3));
    for (int c = 0; c < clutter; ++c) {
      const double u = rng.uniform(0.0, 1240.0), d = rng.uniform(10.0, 200.0);
      Z.emplace_back(u, rng.uniform(0.0, 375.0), u - d);
    }
    (void)cam;
    p.scans.push_back(Z);
  }
  return p;
}

inline double max_position_error(const StereoMlSlam::PoseList& a, const StereoMlSlam::PoseList& b) {
  double e = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    e = std::max(e, (a[k].translation() - b[k].translation()).norm());
  return e;
}

inline MlSlamConfig stereo_config() {
  MlSlamConfig c;
  c.border_range_m = 0.5;
  c.border_pixels = 2.0;
  c.birth_radius_m = 0.5;
  c.merge_distance_m = 0.2;
  return c;
}

/// Solves p from the odometry with `slam` at 1 and at 2 threads and expects the same output, bit for bit.
template <class Solver>
void expect_same_output_at_1_and_2_threads(const Solver& slam, const StereoProblem& p) {
  const int threads = thread_count();
  StereoMlSlam::PoseList x1 = p.odometry, x2 = p.odometry;
  StereoMlSlam::LandmarkList m1 = p.landmarks, m2 = p.landmarks;
  set_thread_count(1);
  const MlSlamReport r1 = slam.solve(x1, p.controls, p.scans, m1);
  set_thread_count(2);
  const MlSlamReport r2 = slam.solve(x2, p.controls, p.scans, m2);
  set_thread_count(threads);
  EXPECT_EQ(r1.final_log_likelihood, r2.final_log_likelihood);
  ASSERT_EQ(m1.size(), m2.size());
  for (std::size_t k = 0; k < x1.size(); ++k) EXPECT_TRUE(x1[k].matrix() == x2[k].matrix());
  for (std::size_t j = 0; j < m1.size(); ++j) EXPECT_EQ(m1[j], m2[j]);
}

}  // namespace glmbslam::backend::test
