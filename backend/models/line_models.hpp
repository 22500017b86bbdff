#pragma once
// Paper 004's 1D SLAM problem (Inostroza & Adams, Sec. VI-A; digest 3.4): a robot on a line measures its own
// displacement and the signed offsets of the landmarks ahead of it, both with additive Gaussian noise.
//   motion:      x_k = x_{k−1} + u_k + w,  w ~ N(0, q)                  (Eq. 2 in one dimension)
//   measurement: z   = m − x + v,          v ~ N(0, r), for min_range ≤ m − x ≤ max_range   (Eq. 3)
// detected with p_D inside that interval, clutter Poisson(λ_c) uniform over it. The interfaces are the 2D
// models' (unicycle_motion.hpp, range_bearing_model.hpp), so the RFS-ML solver takes them as they are
// (backend/mlslam/line_ml_slam.hpp).
#include <cmath>

#include <Eigen/Core>

namespace glmbslam::backend {

using LinePose = Eigen::Matrix<double, 1, 1>;

struct LineMotionConfig {
  double variance = 1e-2;  ///< q, the odometry noise variance per step (m²); paper 004: 1e-2
};

/// x_k = x_{k−1} + u_k with noise N(0, q); State, Tangent, Control and Covariance are 1-vectors.
class LineMotion {
 public:
  static constexpr int kDim = 1;
  using State = LinePose;
  using Tangent = LinePose;
  using Control = LinePose;
  using Covariance = Eigen::Matrix<double, 1, 1>;

  explicit LineMotion(const LineMotionConfig& config = {}) : Q_(Covariance::Constant(config.variance)) {}

  State predict(const State& x, const Control& u) const { return x + u; }
  Covariance process_noise(const State& /*x*/, const Control& /*u*/) const { return Q_; }
  static State retract(const State& x, const Tangent& d) { return x + d; }
  static Tangent local(const State& a, const State& b) { return a - b; }
  /// log N(x − x_prev − u; 0, q)
  double log_density(const State& x, const State& x_prev, const Control& u) const {
    const double e = (x - predict(x_prev, u))(0);
    return -0.5 * (e * e / Q_(0, 0) + std::log(2.0 * M_PI * Q_(0, 0)));
  }

 private:
  Covariance Q_;
};

struct LineSensorConfig {
  double variance = 1e-4;  ///< r, the measurement noise variance (m²); paper 004: 1e-4
  double min_range = 0.5;  ///< the sensor sees landmarks at offsets min_range..max_range ahead (m)
  double max_range = 6.0;
  double p_detect_inside = 0.9;  ///< p_D inside that interval
  double clutter_rate = 0.055;   ///< λ_c per scan (paper 004: intensity 0.01 per m over the 5.5 m interval)
};

/// z = m − x with noise N(0, r), the measurement-model interface of range_bearing_model.hpp.
class LineMeasurementModel {
 public:
  static constexpr int kMeasDim = 1;
  static constexpr int kLandmarkDim = 1;
  static constexpr int kPoseDim = 1;
  using Pose = LinePose;
  using Measurement = Eigen::Matrix<double, 1, 1>;
  using Landmark = Eigen::Matrix<double, 1, 1>;
  using LandmarkCovariance = Eigen::Matrix<double, 1, 1>;
  using MeasurementCovariance = Eigen::Matrix<double, 1, 1>;
  using PoseJacobian = Eigen::Matrix<double, 1, 1>;
  using LandmarkJacobian = Eigen::Matrix<double, 1, 1>;

  explicit LineMeasurementModel(const LineSensorConfig& config = {})
      : config_(config),
        R_(MeasurementCovariance::Constant(config.variance)),
        log_kappa_(std::log(config.clutter_rate / (config.max_range - config.min_range))) {}

  Measurement predict(const Pose& x, const Landmark& m) const { return m - x; }
  Measurement linearize(const Pose& x, const Landmark& m, PoseJacobian* H_x, LandmarkJacobian* H_m) const {
    if (H_x != nullptr) H_x->setConstant(-1.0);
    if (H_m != nullptr) H_m->setConstant(1.0);
    return predict(x, m);
  }
  Measurement residual(const Measurement& z, const Measurement& zhat) const { return z - zhat; }
  const MeasurementCovariance& noise() const { return R_; }
  /// log κ(z) = log(λ_c / (max_range − min_range)): clutter uniform over the interval
  double log_clutter_intensity(const Measurement& /*z*/) const { return log_kappa_; }
  double clutter_rate() const { return config_.clutter_rate; }
  /// m = x + z, P = r
  void initialize(const Pose& x, const Measurement& z, Landmark* m, LandmarkCovariance* P) const {
    *m = x + z;
    if (P != nullptr) *P = R_;
  }
  static Eigen::Matrix<double, 1, 1> position(const Pose& x) { return x; }
  static Eigen::Matrix<double, 1, 1> landmark_position(const Landmark& m) { return m; }
  const LineSensorConfig& config() const { return config_; }

 private:
  LineSensorConfig config_;
  MeasurementCovariance R_;
  double log_kappa_;
};

}  // namespace glmbslam::backend
