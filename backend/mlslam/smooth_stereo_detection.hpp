#pragma once
// The stereo counterpart of smooth_detection.hpp (digest 3.5, pitfalls: a hard field-of-view border makes the
// likelihood of paper 004 Eq. 7 jump): with p = x⁻¹ m in the left camera and z = (u_L, v, u_R) = π(p),
//   p_D(m | x) = p_D,in · σ((d − d_min)/w_d) σ((d_max − d)/w_d) · Π_{image borders} σ(distance to border /
//   w_px)
// with σ the logistic function, d = p_z the depth, the borders u_L ∈ [b, W − b], v ∈ [b, H − b], u_R ≥ b.
// At the border p_D is half its inside value.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "backend/models/stereo_measurement_model.hpp"

namespace glmbslam::backend {

class SmoothStereoDetection {
 public:
  /// width_depth ≤ 0: 2 % of the maximum depth; width_pixels ≤ 0: the pixel σ.
  SmoothStereoDetection(const StereoMeasurementModel& model, double width_depth, double width_pixels)
      : config_(model.config()),
        w_d_(width_depth > 0.0 ? width_depth : 0.02 * model.config().max_depth),
        w_px_(width_pixels > 0.0 ? width_pixels : model.config().pixel_sigma) {
    // a point maybe_in_view lies within depth · √(1 + (u/f_x)² + (v/f_y)²) of the camera centre, with u, v
    // the largest offsets from the principal point that maybe_in_view admits
    const StereoCamera& c = model.camera();
    const double slack = std::max(0.0, 14.0 * w_px_ - config_.border);
    const double u = (std::max(c.cx, model.image_width() - c.cx) + slack) / c.fx;
    const double v = (std::max(c.cy, model.image_height() - c.cy) + slack) / c.fy;
    radius_ = (config_.max_depth + 14.0 * w_d_) * std::sqrt(1.0 + u * u + v * v);
  }

  double operator()(const StereoMeasurementModel& model, const Pose3& x, const Eigen::Vector3d& m,
                    const Eigen::Vector3d& z) const {
    const double depth = (x.linear().transpose() * (m - x.translation())).z();
    if (!(depth > 0.0) || config_.p_detect_inside <= 0.0) return 0.0;
    const double b = config_.border;
    const double W = model.image_width(), H = model.image_height();
    const double t =
        std::min({(depth - config_.min_depth) / w_d_, (config_.max_depth - depth) / w_d_, (z(0) - b) / w_px_,
                  (W - b - z(0)) / w_px_, (z(1) - b) / w_px_, (H - b - z(1)) / w_px_, (z(2) - b) / w_px_});
    if (t < -30.0) return 0.0;  // far outside: p_D < 1e-13
    return config_.p_detect_inside * logistic((depth - config_.min_depth) / w_d_) *
           logistic((config_.max_depth - depth) / w_d_) * logistic((z(0) - b) / w_px_) *
           logistic((W - b - z(0)) / w_px_) * logistic((z(1) - b) / w_px_) *
           logistic((H - b - z(1)) / w_px_) * logistic((z(2) - b) / w_px_);
  }

  /// Landmarks farther than this from the camera centre have p_D < 1e-6·p_D,in (never candidates).
  double query_radius() const { return radius_; }
  /// False where p_D < 1e-6·p_D,in for sure: outside the depth range or the image by 14 widths.
  bool maybe_in_view(const StereoMeasurementModel& model, const Pose3& x, const Eigen::Vector3d& m) const {
    const Eigen::Vector3d p = x.linear().transpose() * (m - x.translation());
    if (p.z() < config_.min_depth - 14.0 * w_d_ || p.z() > config_.max_depth + 14.0 * w_d_ || p.z() <= 0.0)
      return false;
    const Eigen::Vector3d z = model.camera().project(p);
    const double margin = config_.border - 14.0 * w_px_;
    return z(0) >= margin && z(0) <= model.image_width() - margin && z(1) >= margin &&
           z(1) <= model.image_height() - margin && z(2) >= margin;
  }

  /// The world-frame axis-aligned box that holds every m with maybe_in_view(model, x, m): the box of the 8
  /// corners of the frustum (depth range × image rectangle, both widened by 14 widths), which is convex; 1 mm
  /// wider against rounding. For a forward camera a few times smaller than the cube of query_radius().
  std::pair<Eigen::Vector3d, Eigen::Vector3d> view_box(const StereoMeasurementModel& model,
                                                       const Pose3& x) const {
    const StereoCamera& c = model.camera();
    const double margin = config_.border - 14.0 * w_px_;
    const double depths[2] = {std::max(0.0, config_.min_depth - 14.0 * w_d_),
                              config_.max_depth + 14.0 * w_d_};
    const double us[2] = {(margin - c.cx) / c.fx, (model.image_width() - margin - c.cx) / c.fx};
    const double vs[2] = {(margin - c.cy) / c.fy, (model.image_height() - margin - c.cy) / c.fy};
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (double d : depths)
      for (double u : us)
        for (double v : vs) {
          const Eigen::Vector3d corner = x * Eigen::Vector3d(u * d, v * d, d);
          lo = lo.cwiseMin(corner);
          hi = hi.cwiseMax(corner);
        }
    return {lo - Eigen::Vector3d::Constant(1e-3), hi + Eigen::Vector3d::Constant(1e-3)};
  }

 private:
  static double logistic(double t) { return 1.0 / (1.0 + std::exp(-t)); }
  StereoMeasurementConfig config_;
  double w_d_, w_px_, radius_ = 0.0;
};

}  // namespace glmbslam::backend
