#pragma once
// Rectified stereo measurement model (issue 7; paper 000 Sec. 4 uses stereo ORB features):
//   z = (u_L, v, u_R) = π(T_wc⁻¹ m) + ν,   ν ~ N(0, σ² I₃)
// with pose T_wc ∈ SE(3) (left camera, right perturbation of core/lie.hpp) and landmark m ∈ ℝ³ (world).
// Field of view: the projection lies inside the image and the depth in [z_min, z_max]; p_D inside, 0 outside
// (landmark kept); p_S inside/outside; clutter Poisson, uniform over image × disparity range.
// Implements the MeasurementModel concept documented in range_bearing_model.hpp.
//
// Optional appearance term (association.use_descriptors): each landmark keeps the ORB descriptor of its last
// detection, and the single-landmark likelihood g(z_j | m) is multiplied by a descriptor likelihood ratio
//   log p(a_j | m) / p(a_j | clutter) = clamp(scale · (threshold − d_H(a_m, a_j)), ±max_log_ratio)
// (d_H: Hamming distance of 256-bit descriptors; matches of the same point typically have d_H < 50, unrelated
// ORB descriptors ~128). The descriptors of the current measurement set are handed over with
// set_measurement_appearance() before each filter step; copies of the model share them.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/hamming.hpp"
#include "core/lie.hpp"
#include "core/stereo_camera.hpp"
#include "core/types.hpp"

namespace glmbslam::backend {

struct StereoMeasurementConfig {
  double pixel_sigma = 1.0;               ///< σ of each of u_L, v, u_R (pixels)
  double min_depth = 1.0;                 ///< z_min (m)
  double max_depth = 20.0;                ///< z_max (m); paper 000 uses 20 m
  double border = 0.0;                    ///< pixels at the image border counted as outside the view
  double p_detect_inside = 0.7;           ///< p_D in view
  double p_survive_inside = 0.95;         ///< p_S in view
  double p_survive_outside = 1.0;         ///< p_S out of view
  double clutter_rate = 10.0;             ///< λ_c: expected clutter measurements per frame
  bool use_descriptors = false;           ///< multiply g(z|m) by the descriptor likelihood ratio
  double descriptor_threshold = 50.0;     ///< Hamming distance with likelihood ratio 1
  double descriptor_scale = 0.1;          ///< log-ratio per bit of Hamming distance
  double descriptor_max_log_ratio = 5.0;  ///< |log-ratio| cap
};

class StereoMeasurementModel {
 public:
  static constexpr int kMeasDim = 3;
  static constexpr int kLandmarkDim = 3;
  static constexpr int kPoseDim = 6;
  using Pose = Pose3;
  using Measurement = Eigen::Vector3d;
  using Landmark = Eigen::Vector3d;
  using LandmarkCovariance = Eigen::Matrix3d;
  using MeasurementCovariance = Eigen::Matrix3d;
  using PoseJacobian = Eigen::Matrix<double, 3, 6>;
  using LandmarkJacobian = Eigen::Matrix3d;
  using Appearance = Descriptor256;

  StereoMeasurementModel() = default;
  StereoMeasurementModel(const StereoCalibration& calib, const StereoMeasurementConfig& c)
      : camera_(calib), width_(calib.width), height_(calib.height), config_(c) {
    set_pixel_sigma(c.pixel_sigma);
    const double disparity_range = camera_.bf() / c.min_depth - camera_.bf() / c.max_depth;
    const double volume = std::max(1.0, (width_ - 2 * c.border) * (height_ - 2 * c.border) * disparity_range);
    log_kappa_ = c.clutter_rate > 0.0 ? std::log(c.clutter_rate / volume) : std::log(1e-300);
  }
  const StereoMeasurementConfig& config() const { return config_; }
  const StereoCamera& camera() const { return camera_; }
  double image_width() const { return width_; }
  double image_height() const { return height_; }

  Measurement predict(const Pose& x, const Landmark& m) const { return camera_.project_from_pose(x, m); }

  Measurement linearize(const Pose& x, const Landmark& m, PoseJacobian* H_x, LandmarkJacobian* H_m) const {
    return camera_.project_from_pose(x, m, H_x, H_m);
  }

  Measurement residual(const Measurement& z, const Measurement& zhat) const { return z - zhat; }
  const MeasurementCovariance& noise() const { return *R_; }
  /// Sets σ of R = σ² I for the next filter steps (a per-sequence estimate; copies of this model share it, as
  /// they share the appearance). Landmarks already mapped keep their covariances.
  void set_pixel_sigma(double sigma) const { *R_ = Eigen::Matrix3d::Identity() * sigma * sigma; }

  bool in_field_of_view(const Pose& x, const Landmark& m) const {
    const Eigen::Vector3d p = x.linear().transpose() * (m - x.translation());
    if (!(p.z() >= config_.min_depth && p.z() <= config_.max_depth)) return false;
    const Eigen::Vector3d z = camera_.project(p);
    const double lo = config_.border;
    return z.x() >= lo && z.x() < width_ - lo && z.y() >= lo && z.y() < height_ - lo && z.z() >= lo;
  }
  double detection_probability(const Pose& x, const Landmark& m) const {
    return in_field_of_view(x, m) ? config_.p_detect_inside : 0.0;
  }
  double survival_probability(const Pose& x, const Landmark& m) const {
    return in_field_of_view(x, m) ? config_.p_survive_inside : config_.p_survive_outside;
  }
  double log_clutter_intensity(const Measurement& /*z*/) const { return log_kappa_; }
  double clutter_rate() const { return config_.clutter_rate; }

  /// Inverse model: triangulate in the camera frame and move to the world, P = R J R_z Jᵀ Rᵀ.
  void initialize(const Pose& x, const Measurement& z, Landmark* m, LandmarkCovariance* P) const {
    const Eigen::Vector3d p = camera_.triangulate(z);
    const Eigen::Matrix3d J = camera_.triangulate_jacobian(z);
    const Eigen::Matrix3d Rwc = x.linear();
    *m = x * p;
    *P = Rwc * (J * *R_ * J.transpose()) * Rwc.transpose();
    P->diagonal().array() += 1e-9;
  }

  // ----- appearance (see the file comment) -----
  /// Descriptors of the measurement set of the next filter step, index-aligned with it (shared by all copies
  /// of this model). Call before GlmbSlam::initial_scan / step when use_descriptors is on.
  void set_measurement_appearance(std::vector<Appearance> descriptors) const {
    *appearance_ = std::move(descriptors);
  }
  bool uses_appearance() const { return config_.use_descriptors; }
  Appearance measurement_appearance(int j) const {
    return static_cast<std::size_t>(j) < appearance_->size() ? (*appearance_)[static_cast<std::size_t>(j)]
                                                             : Appearance{};
  }
  double log_appearance_ratio(const Appearance& landmark, int j) const {
    if (static_cast<std::size_t>(j) >= appearance_->size()) return 0.0;
    const double d = hamming_distance(landmark, (*appearance_)[static_cast<std::size_t>(j)]);
    const double cap = config_.descriptor_max_log_ratio;
    return std::clamp(config_.descriptor_scale * (config_.descriptor_threshold - d), -cap, cap);
  }

  double query_radius() const { return config_.max_depth * 1.5; }
  static Eigen::Vector3d position(const Pose& x) { return x.translation(); }
  static Eigen::Vector3d landmark_position(const Landmark& m) { return m; }
  /// A usable stereo measurement: finite with a positive disparity.
  bool is_finite(const Measurement& z) const { return z.allFinite() && z.x() - z.z() > 0.0; }

 private:
  StereoCamera camera_;
  double width_ = 0.0;
  double height_ = 0.0;
  StereoMeasurementConfig config_;
  std::shared_ptr<MeasurementCovariance> R_ =
      std::make_shared<MeasurementCovariance>(Eigen::Matrix3d::Identity());
  double log_kappa_ = 0.0;
  std::shared_ptr<std::vector<Appearance>> appearance_ = std::make_shared<std::vector<Appearance>>();
};

}  // namespace glmbslam::backend
