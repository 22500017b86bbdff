#pragma once
// YAML loader of AckermannMotionConfig (keys = member names; the steering noise in degrees).
#include "backend/models/ackermann_motion.hpp"
#include "core/config_node.hpp"

namespace glmbslam::backend {

/// Keys: wheel_base, encoder_offset, laser_forward, laser_lateral, sigma_v, sigma_steer_deg.
/// Unknown keys are errors.
void load_ackermann_motion_config(ConfigNode node, AckermannMotionConfig& config);

}  // namespace glmbslam::backend
