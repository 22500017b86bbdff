#include "sim/scenario_paper004.hpp"

#include <cmath>

#include "core/lie.hpp"
#include "core/random.hpp"

namespace glmbslam::sim {

namespace {

constexpr int kSteps = 30;
constexpr double kSpeed = 0.15;  // m/s
/// Turn rate of each of the 5 segments of 6 steps (straight, turn, straight, turn, straight).
constexpr double kTurnRate[5] = {0.0, 0.3, 0.0, 0.3, 0.0};
constexpr double kPaperClutterIntensity = 0.001;  // per (m · rad)

}  // namespace

Scenario2D make_paper004_scenario(const Paper004Options& o) {
  Scenario2D s;
  s.name = "paper004";
  s.motion = MotionKind::kUnicycleEuler;
  s.dt = 1.0;
  s.sensor.min_range = 0.5;
  s.sensor.max_range = 2.5;
  s.sensor.max_bearing = M_PI;
  s.sensor.detection_probability = 0.9;
  const double volume = (s.sensor.max_range - s.sensor.min_range) * 2.0 * M_PI;
  s.sensor.clutter_rate = o.clutter_rate >= 0.0 ? o.clutter_rate : kPaperClutterIntensity * volume;
  s.sensor.measurement_noise = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();
  s.control_noise = Eigen::Vector2d(2e-4, 2e-4).asDiagonal();

  s.true_controls.emplace_back(0.0, 0.0);
  for (int k = 1; k < kSteps; ++k) s.true_controls.emplace_back(kSpeed, kTurnRate[(k - 1) / 6]);
  s.poses.emplace_back(0.5, -1.0, M_PI);
  for (int k = 1; k < kSteps; ++k) s.poses.push_back(motion_step(s, s.poses.back(), s.true_controls[k]));
  RandomStream layout(4, 1);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d& p = s.poses[static_cast<std::size_t>(3 + 6 * i)];
    const double side = i % 2 == 0 ? 1.0 : -1.0, offset = layout.uniform(0.7, 1.2);
    s.landmarks.emplace_back(p(0) - side * offset * std::sin(p(2)), p(1) + side * offset * std::cos(p(2)));
  }

  RandomStream data(o.data_seed, 2);
  const Eigen::Vector2d sigma_u = s.control_noise.diagonal().cwiseSqrt();
  const Eigen::Vector2d sigma_z = s.sensor.measurement_noise.diagonal().cwiseSqrt();
  s.controls.emplace_back(0.0, 0.0);
  for (int k = 1; k < kSteps; ++k) {
    s.controls.push_back(s.true_controls[static_cast<std::size_t>(k)] +
                         Eigen::Vector2d(sigma_u(0) * data.normal(), sigma_u(1) * data.normal()));
  }
  for (const Eigen::Vector3d& x : s.poses) {
    std::vector<Eigen::Vector2d> z;
    std::vector<int> src;
    for (int i : visible_landmarks(x, s.landmarks, s.sensor)) {
      if (data.uniform() >= s.sensor.detection_probability) continue;
      const Eigen::Vector2d clean = range_bearing(x, s.landmarks[static_cast<std::size_t>(i)]);
      z.emplace_back(clean(0) + sigma_z(0) * data.normal(),
                     wrap_angle(clean(1) + sigma_z(1) * data.normal()));
      src.push_back(i);
    }
    for (int c = data.poisson(s.sensor.clutter_rate); c > 0; --c) {
      z.emplace_back(data.uniform(s.sensor.min_range, s.sensor.max_range), data.uniform(-M_PI, M_PI));
      src.push_back(-1);
    }
    s.measurements.push_back(std::move(z));
    s.measurement_sources.push_back(std::move(src));
  }
  check_scenario(s);
  return s;
}

}  // namespace glmbslam::sim
