#pragma once
// 2D range-bearing measurement model with a field of view (paper 003 Eq. 50; paper 000 Table 1):
//   z = h(x, m) + ν = [‖m − p‖,  atan2(m_y − y, m_x − x) − θ]ᵀ + ν,   ν ~ N(0, R), R = diag(σ_r², σ_b²).
//
// MeasurementModel concept (what backend/glmb and backend/rbpf use):
//   static constexpr int kMeasDim, kLandmarkDim, kPoseDim;
//   using Pose, Measurement, Landmark, LandmarkCovariance, MeasurementCovariance, PoseJacobian
//   (kMeasDim×kPoseDim),
//         LandmarkJacobian (kMeasDim×kLandmarkDim);
//   Measurement predict(const Pose&, const Landmark&) const;
//   Measurement linearize(const Pose&, const Landmark&, PoseJacobian* H_x, LandmarkJacobian* H_m) const;
//       (H_x w.r.t. the pose tangent of the motion model's ⊕; either pointer may be null)
//   Measurement residual(const Measurement& z, const Measurement& zhat) const;   z − ẑ (bearing wrapped)
//   const MeasurementCovariance& noise() const;                                   R
//   bool in_field_of_view(const Pose&, const Landmark&) const;
//   double detection_probability(const Pose&, const Landmark&) const;            p_D (inside / outside)
//   double survival_probability(const Pose&, const Landmark&) const;             p_S (inside / outside)
//   double log_clutter_intensity(const Measurement&) const;                       log κ(z) = log(λ_c / V)
//   double clutter_rate() const;                                                   λ_c
//   void initialize(const Pose&, const Measurement&, Landmark*, LandmarkCovariance*) const;   inverse model
//   double query_radius() const;      landmarks farther than this from position(pose) are never in view
//   static Eigen::Vector2d/3d position(const Pose&), landmark_position(const Landmark&)   for the spatial
//   query bool is_finite(const Measurement&) const;
//
// p_D and p_S are evaluated at the landmark mean (the usual EKF/GM approximation of <p, p_D g>).
#include <cmath>

#include <Eigen/Core>

#include "backend/models/unicycle_motion.hpp"
#include "core/lie.hpp"

namespace glmbslam::backend {

struct RangeBearingConfig {
  double sigma_range = 0.8;                   ///< σ_r (m)
  double sigma_bearing = 0.3 * M_PI / 180.0;  ///< σ_b (rad)
  double min_range = 1e-6;                    ///< landmarks closer than this are out of view (m)
  double max_range = 150.0;                   ///< sensor range (m)
  double half_fov = 0.5 * M_PI;               ///< bearing limit |b| ≤ half_fov (rad); π = 360°
  double p_detect_inside = 0.95;              ///< p_D in the field of view
  double p_detect_outside = 0.0;              ///< p_D outside
  double p_survive_inside = 0.95;             ///< p_S in the field of view
  double p_survive_outside = 1.0;             ///< p_S outside
  double clutter_rate = 5.0;                  ///< λ_c, expected clutter points per scan
  /// Clutter density κ(z) = λ_c / V. V ≤ 0 (default): the range-bearing volume (max−min range)·2·half_fov.
  double clutter_volume = 0.0;
};

class RangeBearingModel {
 public:
  static constexpr int kMeasDim = 2;
  static constexpr int kLandmarkDim = 2;
  static constexpr int kPoseDim = 3;
  using Pose = Pose2;
  using Measurement = Eigen::Vector2d;
  using Landmark = Eigen::Vector2d;
  using LandmarkCovariance = Eigen::Matrix2d;
  using MeasurementCovariance = Eigen::Matrix2d;
  using PoseJacobian = Eigen::Matrix<double, 2, 3>;
  using LandmarkJacobian = Eigen::Matrix2d;

  RangeBearingModel() : RangeBearingModel(RangeBearingConfig{}) {}
  explicit RangeBearingModel(const RangeBearingConfig& c) : config_(c) {
    R_ = Eigen::Vector2d(c.sigma_range * c.sigma_range, c.sigma_bearing * c.sigma_bearing).asDiagonal();
    const double volume =
        c.clutter_volume > 0.0 ? c.clutter_volume : (c.max_range - c.min_range) * 2.0 * c.half_fov;
    log_kappa_ = c.clutter_rate > 0.0 ? std::log(c.clutter_rate / volume) : std::log(1e-300);
  }
  const RangeBearingConfig& config() const { return config_; }

  Measurement predict(const Pose& x, const Landmark& m) const {
    const double dx = m(0) - x(0), dy = m(1) - x(1);
    return Measurement(std::sqrt(dx * dx + dy * dy), wrap_angle(std::atan2(dy, dx) - x(2)));
  }

  /// ẑ and the Jacobians at (x, m). At range 0 the Jacobians are set to zero (such a landmark is out of
  /// view).
  Measurement linearize(const Pose& x, const Landmark& m, PoseJacobian* H_x, LandmarkJacobian* H_m) const {
    const double dx = m(0) - x(0), dy = m(1) - x(1);
    const double q = dx * dx + dy * dy;
    const double r = std::sqrt(q);
    LandmarkJacobian Hm = LandmarkJacobian::Zero();
    if (q > 1e-24) Hm << dx / r, dy / r, -dy / q, dx / q;
    if (H_m != nullptr) *H_m = Hm;
    if (H_x != nullptr) {
      H_x->leftCols<2>() = -Hm;
      H_x->col(2) << 0.0, -1.0;
    }
    return Measurement(r, wrap_angle(std::atan2(dy, dx) - x(2)));
  }

  Measurement residual(const Measurement& z, const Measurement& zhat) const {
    return Measurement(z(0) - zhat(0), wrap_angle(z(1) - zhat(1)));
  }

  const MeasurementCovariance& noise() const { return R_; }

  bool in_field_of_view(const Pose& x, const Landmark& m) const {
    const double dx = m(0) - x(0), dy = m(1) - x(1);
    const double q = dx * dx + dy * dy;
    if (q > config_.max_range * config_.max_range || q < config_.min_range * config_.min_range) return false;
    return std::abs(wrap_angle(std::atan2(dy, dx) - x(2))) <= config_.half_fov;
  }
  double detection_probability(const Pose& x, const Landmark& m) const {
    return in_field_of_view(x, m) ? config_.p_detect_inside : config_.p_detect_outside;
  }
  double survival_probability(const Pose& x, const Landmark& m) const {
    if (config_.p_survive_inside == config_.p_survive_outside)
      return config_.p_survive_inside;  // no FOV test
    return in_field_of_view(x, m) ? config_.p_survive_inside : config_.p_survive_outside;
  }
  double log_clutter_intensity(const Measurement& /*z*/) const { return log_kappa_; }
  double clutter_rate() const { return config_.clutter_rate; }

  /// Inverse model: m = p + r (cos(θ + b), sin(θ + b)), P = G_z R G_zᵀ.
  void initialize(const Pose& x, const Measurement& z, Landmark* m, LandmarkCovariance* P) const {
    const double a = x(2) + z(1), c = std::cos(a), s = std::sin(a);
    *m << x(0) + z(0) * c, x(1) + z(0) * s;
    Eigen::Matrix2d G;
    G << c, -z(0) * s, s, z(0) * c;
    *P = G * R_ * G.transpose();
    // keep P positive definite even at zero range
    P->diagonal().array() += 1e-12;
  }

  double query_radius() const { return config_.max_range; }
  static Eigen::Vector2d position(const Pose& x) { return x.head<2>(); }
  static Eigen::Vector2d landmark_position(const Landmark& m) { return m; }
  bool is_finite(const Measurement& z) const { return z.allFinite(); }

 private:
  RangeBearingConfig config_;
  MeasurementCovariance R_;
  double log_kappa_ = 0.0;
};

}  // namespace glmbslam::backend
