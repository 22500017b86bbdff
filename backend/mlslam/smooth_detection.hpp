#pragma once
// A detection probability with a smooth field-of-view border for RFS-ML-SLAM (digest 3.5, pitfalls): with a
// hard border the likelihood of paper 004 (Eq. 7) jumps whenever a landmark crosses it, so the gradient-based
// M-step and the comparisons of the cardinality moves see a discontinuous objective. Here
//   p_D(m | x) = p_D,in(m | x) · σ((r_max − r)/w_r) · σ((r − r_min)/w_r) · σ((φ − |b|)/w_b)
// with σ the logistic function, (r, b) = h(x, m) and p_D,in the model's detection probability inside the
// field of view (the bearing factor is left out for a 360° sensor). At the border p_D is half its inside
// value; w_r, w_b a few noise standard deviations wide.
#include <algorithm>
#include <cmath>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/victoria_park_measurement.hpp"

namespace glmbslam::backend {

/// p_D inside the field of view, for the 2D range-bearing models.
inline double interior_detection_probability(const RangeBearingModel& model, const Pose2& /*x*/,
                                             const Eigen::Vector2d& /*m*/, double /*range*/) {
  return model.config().p_detect_inside;
}
inline double interior_detection_probability(const VictoriaParkMeasurement& model, const Pose2& /*x*/,
                                             const Eigen::Vector2d& /*m*/, double range) {
  return model.config().p_detect_inside * std::max(0.0, 1.0 - range / model.config().max_range);
}

class SmoothDetection2D {
 public:
  /// width_range / width_bearing ≤ 0: the model's σ_r / σ_b.
  template <class Model>
  SmoothDetection2D(const Model& model, double width_range, double width_bearing)
      : config_(model.config()),
        w_r_(width_range > 0.0 ? width_range : model.config().sigma_range),
        w_b_(width_bearing > 0.0 ? width_bearing : model.config().sigma_bearing) {}

  /// p_D(m | x) for a landmark whose predicted measurement is z = (r, b).
  template <class Model>
  double operator()(const Model& model, const Pose2& x, const Eigen::Vector2d& m,
                    const Eigen::Vector2d& z) const {
    const double p_in = interior_detection_probability(model, x, m, z(0));
    if (p_in <= 0.0) return 0.0;
    double p =
        p_in * logistic((config_.max_range - z(0)) / w_r_) * logistic((z(0) - config_.min_range) / w_r_);
    if (config_.half_fov < M_PI - 1e-9) p *= logistic((config_.half_fov - std::abs(z(1))) / w_b_);
    return p;
  }

  /// Landmarks farther than this from the pose have p_D < 1e-6·p_D,in (never candidates).
  double query_radius() const { return config_.max_range + 14.0 * w_r_; }
  /// False where p_D < 1e-6·p_D,in for sure (the landmark is no candidate of the scan).
  template <class Model>
  bool maybe_in_view(const Model& /*model*/, const Pose2& x, const typename Model::Landmark& m) const {
    return (Model::landmark_position(m) - Model::position(x)).norm() <= query_radius();
  }

 private:
  static double logistic(double t) { return 1.0 / (1.0 + std::exp(-t)); }
  RangeBearingConfig config_;
  double w_r_, w_b_;
};

}  // namespace glmbslam::backend
