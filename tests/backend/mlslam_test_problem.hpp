#pragma once
// A small 2D range-bearing SLAM problem for the RFS-ML-SLAM tests: a unicycle loop around a handful of
// landmarks, noisy odometry and measurement sets with misses and Poisson clutter, all from a seeded stream.
#include <cmath>
#include <vector>

#include "backend/mlslam/rfs_ml_slam.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "core/random.hpp"

namespace glmbslam::backend::test {

using Slam2D = RfsMlSlam<UnicycleMotion, RangeBearingModel>;

struct Problem2D {
  UnicycleMotion motion;
  RangeBearingModel model;
  Slam2D::PoseList truth;
  Slam2D::LandmarkList landmarks;
  Slam2D::ControlList controls;
  std::vector<Slam2D::MeasurementSet> scans;
  Slam2D::PoseList odometry;  ///< dead reckoning from x_0 with the noisy controls
};

/// K steps on a circle of radius 4 m around `count` landmarks; p_D, clutter rate λ_c per scan; a sensor
/// range below 6 m leaves the far landmarks out of view.
inline Problem2D make_problem(int K, int count, double p_D, double clutter, std::uint64_t seed,
                              double max_range = 8.0) {
  UnicycleMotionConfig mc;
  mc.sigma_v = 0.02;
  mc.sigma_omega = 0.01;
  RangeBearingConfig rc;
  rc.sigma_range = 0.02;
  rc.sigma_bearing = 0.01;
  rc.max_range = max_range;
  rc.half_fov = M_PI;
  rc.p_detect_inside = p_D;
  rc.clutter_rate = clutter;
  Problem2D p{UnicycleMotion(mc), RangeBearingModel(rc), {}, {}, {}, {}, {}};
  RandomStream rng(seed, 7);
  for (int j = 0; j < count; ++j) {
    const double a = 2.0 * M_PI * j / count;
    p.landmarks.emplace_back(2.0 * std::cos(a) + 0.5 * std::sin(3.0 * a), 2.0 * std::sin(a));
  }
  const Eigen::Vector2d u_true(0.5, 0.5 / 4.0);
  p.truth.emplace_back(4.0, 0.0, M_PI / 2);
  p.odometry.push_back(p.truth[0]);
  p.controls.emplace_back(0.0, 0.0);
  for (int k = 1; k < K; ++k) {
    p.truth.push_back(p.motion.predict(p.truth.back(), u_true));
    const Eigen::Vector2d u(u_true(0) + mc.sigma_v * rng.normal(), u_true(1) + mc.sigma_omega * rng.normal());
    p.controls.push_back(u);
    p.odometry.push_back(p.motion.predict(p.odometry.back(), u));
  }
  for (const auto& x : p.truth) {
    Slam2D::MeasurementSet Z;
    for (const auto& m : p.landmarks) {
      if (!p.model.in_field_of_view(x, m) || rng.uniform() >= p_D) continue;
      const Eigen::Vector2d z = p.model.predict(x, m);
      Z.emplace_back(z(0) + rc.sigma_range * rng.normal(),
                     wrap_angle(z(1) + rc.sigma_bearing * rng.normal()));
    }
    const int n = rng.poisson(clutter);
    for (int c = 0; c < n; ++c)
      Z.emplace_back(rng.uniform(rc.min_range, rc.max_range), rng.uniform(-M_PI, M_PI));
    p.scans.push_back(Z);
  }
  return p;
}

inline double max_position_error(const Slam2D::PoseList& a, const Slam2D::PoseList& b) {
  double e = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) e = std::max(e, (a[k].head<2>() - b[k].head<2>()).norm());
  return e;
}

}  // namespace glmbslam::backend::test
