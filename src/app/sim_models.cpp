#include "app/sim_models.hpp"

#include <algorithm>
#include <cmath>

namespace glmbslam::app {

backend::RangeBearingModel sim_measurement_model(const sim::Scenario2D& s) {
  backend::RangeBearingConfig c;
  c.sigma_range = std::sqrt(s.sensor.measurement_noise(0, 0));
  c.sigma_bearing = std::sqrt(s.sensor.measurement_noise(1, 1));
  c.min_range = std::max(s.sensor.min_range, c.min_range);
  c.max_range = s.sensor.max_range;
  c.half_fov = s.sensor.max_bearing;
  c.p_detect_inside = s.sensor.detection_probability;
  c.clutter_rate = s.sensor.clutter_rate;
  c.clutter_volume = (s.sensor.max_range - s.sensor.min_range) * 2.0 * s.sensor.max_bearing;
  if (s.name == "phdslam3") {
    // The filters' models equal the generator (src/sim/scenario_phdslam3.cpp): its landmarks never disappear,
    // so p_S = 1 in view (paper 000's 0.95 made mapped landmarks die after two misses, e.g. where the
    // estimated field of view edge differs from the true one: ~7 of 160 missing from the final maps), and it
    // thins the Poisson(5) clutter with p_D, so the clutter rate is λ_c·p_D = 4.75 per scan.
    c.p_survive_inside = 1.0;
    c.clutter_rate = s.sensor.clutter_rate * s.sensor.detection_probability;
  }
  return backend::RangeBearingModel(c);
}

backend::UnicycleMotionConfig sim_unicycle_config(const sim::Scenario2D& s) {
  backend::UnicycleMotionConfig mc;
  mc.dt = s.dt;
  mc.sigma_v = std::sqrt(s.control_noise(0, 0));
  mc.sigma_omega = std::sqrt(s.control_noise(1, 1));
  mc.euler = true;  // the phdslam3 ground truth is the Euler step (scenario2d.hpp)
  return mc;
}

backend::SteeringMotionConfig sim_steering_config(const sim::Scenario2D& s) {
  backend::SteeringMotionConfig mc;
  mc.dt = s.dt;
  mc.wheel_base = s.wheel_base;
  mc.sigma_v = std::sqrt(s.control_noise(0, 0));
  mc.sigma_steer = std::sqrt(s.control_noise(1, 1));
  return mc;
}

}  // namespace glmbslam::app
