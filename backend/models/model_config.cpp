#include "backend/models/model_config.hpp"

namespace glmbslam::backend {
namespace {
constexpr double kDeg = M_PI / 180.0;

void read_degrees(ConfigNode& node, const std::string& key, double& radians, double lo_deg, double hi_deg) {
  double deg = radians / kDeg;
  node.read_in_range(key, deg, lo_deg, hi_deg);
  radians = deg * kDeg;
}
}  // namespace

void load_unicycle_motion_config(ConfigNode node, UnicycleMotionConfig& config) {
  node.read_in_range("dt", config.dt, 1e-6, 1e6);
  node.read_in_range("sigma_v", config.sigma_v, 0.0, 1e6);
  read_degrees(node, "sigma_omega_deg", config.sigma_omega, 0.0, 360.0);
  node.read("euler", config.euler);
  node.finish();
}

void load_steering_motion_config(ConfigNode node, SteeringMotionConfig& config) {
  node.read_in_range("dt", config.dt, 1e-6, 1e6);
  node.read_in_range("wheel_base", config.wheel_base, 1e-6, 1e3);
  node.read_in_range("sigma_v", config.sigma_v, 0.0, 1e6);
  read_degrees(node, "sigma_steer_deg", config.sigma_steer, 0.0, 360.0);
  node.finish();
}

void load_range_bearing_config(ConfigNode node, RangeBearingConfig& config) {
  node.read_in_range("sigma_range", config.sigma_range, 1e-9, 1e6);
  read_degrees(node, "sigma_bearing_deg", config.sigma_bearing, 1e-9, 360.0);
  node.read_in_range("min_range", config.min_range, 0.0, 1e9);
  node.read_in_range("max_range", config.max_range, 1e-9, 1e9);
  read_degrees(node, "half_fov_deg", config.half_fov, 0.0, 180.0);
  node.read_in_range("p_detect_inside", config.p_detect_inside, 0.0, 1.0);
  node.read_in_range("p_detect_outside", config.p_detect_outside, 0.0, 1.0);
  node.read_in_range("p_survive_inside", config.p_survive_inside, 0.0, 1.0);
  node.read_in_range("p_survive_outside", config.p_survive_outside, 0.0, 1.0);
  node.read_in_range("clutter_rate", config.clutter_rate, 0.0, 1e6);
  node.read_in_range("clutter_volume", config.clutter_volume, 0.0, 1e12);
  if (config.min_range >= config.max_range) node.fail("min_range", "must be smaller than max_range");
  node.finish();
}

}  // namespace glmbslam::backend
