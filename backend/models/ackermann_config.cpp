#include "backend/models/ackermann_config.hpp"

namespace glmbslam::backend {

void load_ackermann_motion_config(ConfigNode node, AckermannMotionConfig& config) {
  node.read_in_range("wheel_base", config.wheel_base, 1e-3, 100.0);
  node.read_in_range("encoder_offset", config.encoder_offset, -100.0, 100.0);
  node.read_in_range("laser_forward", config.laser_forward, -100.0, 100.0);
  node.read_in_range("laser_lateral", config.laser_lateral, -100.0, 100.0);
  node.read_in_range("sigma_v", config.sigma_v, 0.0, 1e3);
  double deg = config.sigma_steer * 180.0 / M_PI;
  node.read_in_range("sigma_steer_deg", deg, 0.0, 180.0);
  config.sigma_steer = deg * M_PI / 180.0;
  node.finish();
}

}  // namespace glmbslam::backend
