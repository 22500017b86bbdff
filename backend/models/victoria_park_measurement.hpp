#pragma once
// Range-bearing measurement model of the Victoria Park protocol (paper 003 Sec. VI-B; digest 2.6): the
// RangeBearingModel with a range-dependent detection probability inside the field of view,
//   p_D(m | x) = p_D0 · (1 − ‖m − x‖ / r_max)   in the field of view (|bearing| ≤ half_fov, range ≤ r_max),
//   p_D = p_detect_outside (0) outside,
// evaluated at the landmark mean (the usual approximation). Everything else (h, Jacobians, R, clutter
// intensity λ/V with V = (r_max − r_min)·2·half_fov in (range, bearing) space, which matches clutter drawn
// uniformly in range and bearing) is RangeBearingModel's. The class is used as a template parameter, so the
// hiding detection_probability below is the one the filters call.
#include <algorithm>

#include "backend/models/range_bearing_model.hpp"

namespace glmbslam::backend {

class VictoriaParkMeasurement : public RangeBearingModel {
 public:
  VictoriaParkMeasurement() : VictoriaParkMeasurement(default_config()) {}
  explicit VictoriaParkMeasurement(const RangeBearingConfig& config) : RangeBearingModel(config) {}

  /// p_D0·(1 − r/r_max) in view (p_D0 = config.p_detect_inside), p_detect_outside otherwise.
  double detection_probability(const Pose& x, const Landmark& m) const {
    if (!in_field_of_view(x, m)) return config().p_detect_outside;
    const double r = (m - x.head<2>()).norm();
    return config().p_detect_inside * std::max(0.0, 1.0 - r / config().max_range);
  }

  /// The published constants: σ_r = 1 m, σ_b = 1°, ±85°, 50 m, p_D0 = 0.7, p_S = 1, λ = 5.
  static RangeBearingConfig default_config() {
    RangeBearingConfig c;
    c.sigma_range = 1.0;
    c.sigma_bearing = M_PI / 180.0;
    c.max_range = 50.0;
    c.half_fov = 85.0 * M_PI / 180.0;
    c.p_detect_inside = 0.7;
    c.p_detect_outside = 0.0;
    c.p_survive_inside = 1.0;
    c.p_survive_outside = 1.0;
    c.clutter_rate = 5.0;
    return c;
  }
};

}  // namespace glmbslam::backend
