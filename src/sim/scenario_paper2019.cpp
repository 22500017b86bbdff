#include "sim/scenario_paper2019.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/random.hpp"

namespace glmbslam::sim {

namespace {

constexpr int kStraightLongSteps = 26;   // 6.5 m at 1 m/s, dt 0.25
constexpr int kStraightShortSteps = 12;  // 3 m
constexpr int kTurnSteps = 12;           // 90° in 12 steps
constexpr int kRevisitSteps = 27;        // re-driven part of the first straight after the lap
constexpr int kLandmarkCount = 23;

/// Noise-free (v, G) for step k ≥ 1 of the path.
std::vector<Eigen::Vector2d> path_controls(const Paper2019Options& o) {
  const double per_step = (M_PI / 2.0) / kTurnSteps;  // heading change per turn step
  const double sin_g = per_step * o.wheel_base / (o.speed * o.dt);
  if (sin_g >= 1.0)
    throw std::invalid_argument("paper2019: wheel base too long for the turns at this speed/dt");
  const double steer = std::asin(sin_g);
  std::vector<Eigen::Vector2d> lap;
  const int straights[4] = {kStraightLongSteps, kStraightShortSteps, kStraightLongSteps, kStraightShortSteps};
  for (int side = 0; side < 4; ++side) {
    for (int i = 0; i < straights[side]; ++i) lap.emplace_back(o.speed, 0.0);
    for (int i = 0; i < kTurnSteps; ++i) lap.emplace_back(o.speed, steer);
  }
  std::vector<Eigen::Vector2d> controls;
  controls.emplace_back(0.0, 0.0);  // u_0 unused
  controls.insert(controls.end(), lap.begin(), lap.end());
  for (int i = 0; i < kRevisitSteps; ++i) controls.emplace_back(o.speed, 0.0);
  return controls;
}

}  // namespace

Scenario2D make_paper2019_scenario(const Paper2019Options& o) {
  if (!(o.clutter_rate >= 0.0)) throw std::invalid_argument("paper2019: clutter rate must be non-negative");
  if (!(o.dt > 0.0) || !(o.speed > 0.0))
    throw std::invalid_argument("paper2019: dt and speed must be positive");

  Scenario2D s;
  s.name = "paper2019";
  s.dt = o.dt;
  s.motion = MotionKind::kSteering;
  s.wheel_base = o.wheel_base;
  s.motion = MotionKind::kSteering;
  s.wheel_base = o.wheel_base;
  s.sensor.min_range = 0.0;
  s.sensor.max_range = o.max_range;
  s.sensor.max_bearing = M_PI;
  s.sensor.detection_probability = o.detection_probability;
  s.sensor.clutter_rate = o.clutter_rate;
  const double sigma_b = o.sigma_bearing_deg * M_PI / 180.0;
  s.sensor.measurement_noise = Eigen::Vector2d(o.sigma_range * o.sigma_range, sigma_b * sigma_b).asDiagonal();
  const double sigma_w = o.sigma_steer_deg * M_PI / 180.0;
  s.control_noise = Eigen::Vector2d(o.sigma_speed * o.sigma_speed, sigma_w * sigma_w).asDiagonal();

  // Ground truth.
  s.true_controls = path_controls(o);
  const std::size_t steps = s.true_controls.size();
  s.poses.reserve(steps);
  s.poses.emplace_back(0.0, 0.0, 0.0);
  for (std::size_t k = 1; k < steps; ++k)
    s.poses.push_back(motion_step(s, s.poses.back(), s.true_controls[k]));

  // Landmark layout: evenly along the lap, alternately left/right of the path.
  const int lap_steps = static_cast<int>(steps) - 1 - kRevisitSteps;
  RandomStream layout(o.data_seed, 1);
  for (int i = 0; i < kLandmarkCount; ++i) {
    const double s_along = (i + 0.5) * lap_steps / kLandmarkCount + layout.uniform(-1.0, 1.0);
    const int k = std::clamp(static_cast<int>(std::lround(s_along)), 0, lap_steps);
    const Eigen::Vector3d& p = s.poses[static_cast<std::size_t>(k)];
    const double side = (i % 2 == 0) ? 1.0 : -1.0;  // + = left (inside the counter-clockwise loop)
    const double offset = layout.uniform(0.8, 1.8);
    s.landmarks.emplace_back(p(0) - side * offset * std::sin(p(2)), p(1) + side * offset * std::cos(p(2)));
  }

  // The data realisation: odometry noise and detections (shared by every clutter rate), clutter per rate.
  RandomStream data(o.data_seed, 2);
  const auto clutter_stream_id = static_cast<std::uint64_t>(1000 + std::llround(o.clutter_rate * 1000.0));
  RandomStream clutter(o.data_seed, clutter_stream_id);
  const Eigen::Matrix2d chol_q = s.control_noise.llt().matrixL();
  const Eigen::Matrix2d chol_r = s.sensor.measurement_noise.llt().matrixL();
  s.controls.resize(steps, Eigen::Vector2d::Zero());
  s.measurements.resize(steps);
  s.measurement_sources.resize(steps);
  for (std::size_t k = 0; k < steps; ++k) {
    if (k > 0) s.controls[k] = s.true_controls[k] + chol_q * Eigen::Vector2d(data.normal(), data.normal());
    std::vector<Eigen::Vector2d> z;
    std::vector<int> src;
    for (std::size_t i = 0; i < s.landmarks.size(); ++i) {
      const Eigen::Vector2d clean = range_bearing(s.poses[k], s.landmarks[i]);
      const bool visible = s.sensor.in_field_of_view(clean(0), clean(1));
      // Draw the detection and noise for every landmark, visible or not, so that the stream is consumed in
      // the same way whatever the geometry.
      const double u = data.uniform();
      const Eigen::Vector2d noise = chol_r * Eigen::Vector2d(data.normal(), data.normal());
      if (visible && u < s.sensor.detection_probability) {
        Eigen::Vector2d zi = clean + noise;
        zi(0) = std::max(zi(0), 0.0);
        zi(1) = std::remainder(zi(1), 2.0 * M_PI);
        z.push_back(zi);
        src.push_back(static_cast<int>(i));
      }
    }
    const int n_clutter = clutter.poisson(o.clutter_rate);
    for (int c = 0; c < n_clutter; ++c) {
      const double r = clutter.uniform(s.sensor.min_range, s.sensor.max_range);
      const double b = clutter.uniform(-s.sensor.max_bearing, s.sensor.max_bearing);
      z.emplace_back(r, b);
      src.push_back(-1);
    }
    // Shuffle (Fisher–Yates with the clutter stream) so that filters cannot rely on the order.
    for (std::size_t i = z.size(); i > 1; --i) {
      const std::size_t j = clutter.index(i);
      std::swap(z[i - 1], z[j]);
      std::swap(src[i - 1], src[j]);
    }
    s.measurements[k] = std::move(z);
    s.measurement_sources[k] = std::move(src);
  }
  check_scenario(s);
  return s;
}

}  // namespace glmbslam::sim
