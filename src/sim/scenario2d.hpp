#pragma once
// A 2D range-bearing SLAM scenario: ground truth, noisy odometry, per-step measurement sets and the
// sensor/noise parameters the filters should use. Shared by the paper simulations (paper2019, phdslam3) and
// `glmbslam sim`.
//
// Conventions (identical to the phdslam3 benchmark data, checked against it to 1e-12 in the tests):
//  - pose x_k = (x, y, θ) [m, m, rad], θ wrapped to (−π, π];
//  - control u_k drives pose k−1 to pose k (u_0 is unused and zero), with one of two motion models:
//    MotionKind::kUnicycleEuler, u = (v, ω) [m/s, rad/s] (the phdslam3 data):
//      x_k = x_{k−1} + dt·v·cos θ_{k−1},  y_k = y_{k−1} + dt·v·sin θ_{k−1},  θ_k = wrap(θ_{k−1} + dt·ω);
//    MotionKind::kSteering, u = (v, G) [m/s, rad], wheel base L (paper 000's simulator family, the same as
//    backend/models/steering_motion.hpp):
//      x_k = x_{k−1} + dt·v·cos(θ_{k−1} + G),  y_k = y_{k−1} + dt·v·sin(θ_{k−1} + G),
//      θ_k = wrap(θ_{k−1} + dt·v·sin(G)/L);
//  - measurement z = (r, b): r = ‖m − p_k‖, b = wrap(atan2(m_y − y_k, m_x − x_k) − θ_k);
//    measurement set Z_k is taken at pose k, for every k = 0..K−1 (Z_0 at the initial pose);
//  - a landmark is in the field of view when min_range ≤ r ≤ max_range and |b| ≤ max_bearing;
//  - clutter is Poisson(clutter_rate) per scan, uniform in (r, b) over [min_range, max_range] ×
//  [−max_bearing,
//    max_bearing], so its intensity in measurement space is clutter_intensity() = λ / (range span · bearing
//    span).
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::sim {

/// Sensor and noise parameters of a scenario (the filters' models are built from these).
struct SensorParameters2D {
  double min_range = 0.0;            ///< [m]
  double max_range = 0.0;            ///< [m]
  double max_bearing = 0.0;          ///< half field of view [rad] (π for a 360° sensor)
  double detection_probability = 0;  ///< p_D inside the field of view
  double clutter_rate = 0.0;         ///< λ_c, expected clutter points per scan
  Eigen::Matrix2d measurement_noise = Eigen::Matrix2d::Zero();  ///< R on (r, b) [m², rad²]

  /// Clutter intensity κ(z) in (r, b) space [1/(m·rad)]: λ_c over the area of the field of view in (r, b).
  double clutter_intensity() const;
  /// True when the point (r, b) is inside the field of view.
  bool in_field_of_view(double range, double bearing) const;
};

enum class MotionKind { kUnicycleEuler, kSteering };

struct Scenario2D {
  std::string name;
  MotionKind motion = MotionKind::kUnicycleEuler;
  double wheel_base = 1.0;                     ///< L [m] (kSteering only)
  double dt = 1.0;                             ///< [s]
  std::vector<Eigen::Vector3d> poses;          ///< ground truth (x, y, θ), one per step k = 0..K−1
  std::vector<Eigen::Vector2d> landmarks;      ///< ground-truth landmark positions
  std::vector<Eigen::Vector2d> true_controls;  ///< noise-free (v, ω) per step; [0] unused (zero)
  std::vector<Eigen::Vector2d> controls;       ///< noisy odometry (v, ω) per step; [0] unused (zero)
  std::vector<std::vector<Eigen::Vector2d>> measurements;  ///< Z_k: (r, b) per step
  /// Source of each measurement: landmark index, or −1 for clutter (for data-association statistics).
  std::vector<std::vector<int>> measurement_sources;
  Eigen::Matrix2d control_noise = Eigen::Matrix2d::Zero();  ///< Q on the control (v, ω) or (v, G)
  SensorParameters2D sensor;

  std::size_t steps() const { return poses.size(); }
  const Eigen::Vector3d& initial_pose() const { return poses.front(); }
};

/// The unicycle (Euler) step of the convention above.
Eigen::Vector3d unicycle_step(const Eigen::Vector3d& pose, const Eigen::Vector2d& control, double dt);
/// The steering step of the convention above.
Eigen::Vector3d steering_step(const Eigen::Vector3d& pose, const Eigen::Vector2d& control, double dt,
                              double wheel_base);
/// The scenario's own motion step.
Eigen::Vector3d motion_step(const Scenario2D& scenario, const Eigen::Vector3d& pose,
                            const Eigen::Vector2d& control);

/// Noise-free range-bearing measurement of landmark m from pose x.
Eigen::Vector2d range_bearing(const Eigen::Vector3d& pose, const Eigen::Vector2d& landmark);

/// Inverse measurement: the landmark position seen at (r, b) from pose x.
Eigen::Vector2d inverse_range_bearing(const Eigen::Vector3d& pose, const Eigen::Vector2d& z);

/// Landmarks visible from a pose (noise-free measurement inside the field of view), as indices.
std::vector<int> visible_landmarks(const Eigen::Vector3d& pose, const std::vector<Eigen::Vector2d>& landmarks,
                                   const SensorParameters2D& sensor);

/// Throws std::logic_error if the scenario's vectors are inconsistent (sizes, non-finite values).
void check_scenario(const Scenario2D& scenario);

}  // namespace glmbslam::sim
