#include "sim/scenario2d.hpp"

#include <cmath>
#include <stdexcept>

#include "core/lie.hpp"

namespace glmbslam::sim {

double SensorParameters2D::clutter_intensity() const {
  const double area = (max_range - min_range) * 2.0 * max_bearing;
  return area > 0.0 ? clutter_rate / area : 0.0;
}

bool SensorParameters2D::in_field_of_view(double range, double bearing) const {
  return range >= min_range && range <= max_range && std::abs(bearing) <= max_bearing;
}

Eigen::Vector3d unicycle_step(const Eigen::Vector3d& pose, const Eigen::Vector2d& control, double dt) {
  const double th = pose(2);
  return Eigen::Vector3d(pose(0) + dt * control(0) * std::cos(th), pose(1) + dt * control(0) * std::sin(th),
                         wrap_angle(th + dt * control(1)));
}

Eigen::Vector3d steering_step(const Eigen::Vector3d& pose, const Eigen::Vector2d& control, double dt,
                              double wheel_base) {
  const double a = pose(2) + control(1);
  return Eigen::Vector3d(pose(0) + dt * control(0) * std::cos(a), pose(1) + dt * control(0) * std::sin(a),
                         wrap_angle(pose(2) + dt * control(0) * std::sin(control(1)) / wheel_base));
}

Eigen::Vector3d motion_step(const Scenario2D& s, const Eigen::Vector3d& pose,
                            const Eigen::Vector2d& control) {
  return s.motion == MotionKind::kSteering ? steering_step(pose, control, s.dt, s.wheel_base)
                                           : unicycle_step(pose, control, s.dt);
}

Eigen::Vector2d range_bearing(const Eigen::Vector3d& pose, const Eigen::Vector2d& landmark) {
  const double dx = landmark(0) - pose(0);
  const double dy = landmark(1) - pose(1);
  return Eigen::Vector2d(std::hypot(dx, dy), wrap_angle(std::atan2(dy, dx) - pose(2)));
}

Eigen::Vector2d inverse_range_bearing(const Eigen::Vector3d& pose, const Eigen::Vector2d& z) {
  const double a = pose(2) + z(1);
  return Eigen::Vector2d(pose(0) + z(0) * std::cos(a), pose(1) + z(0) * std::sin(a));
}

std::vector<int> visible_landmarks(const Eigen::Vector3d& pose, const std::vector<Eigen::Vector2d>& landmarks,
                                   const SensorParameters2D& sensor) {
  std::vector<int> out;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const Eigen::Vector2d z = range_bearing(pose, landmarks[i]);
    if (sensor.in_field_of_view(z(0), z(1))) out.push_back(static_cast<int>(i));
  }
  return out;
}

void check_scenario(const Scenario2D& s) {
  const std::size_t k = s.poses.size();
  if (k == 0) throw std::logic_error("scenario " + s.name + ": no poses");
  if (s.controls.size() != k || s.true_controls.size() != k || s.measurements.size() != k ||
      s.measurement_sources.size() != k) {
    throw std::logic_error("scenario " + s.name + ": per-step vectors differ in length");
  }
  for (std::size_t i = 0; i < k; ++i) {
    if (!s.poses[i].allFinite() || !s.controls[i].allFinite()) {
      throw std::logic_error("scenario " + s.name + ": non-finite pose or control at step " +
                             std::to_string(i));
    }
    if (s.measurements[i].size() != s.measurement_sources[i].size()) {
      throw std::logic_error("scenario " + s.name + ": measurement sources differ at step " +
                             std::to_string(i));
    }
  }
  if (!(s.dt > 0.0)) throw std::logic_error("scenario " + s.name + ": dt must be positive");
}

}  // namespace glmbslam::sim
