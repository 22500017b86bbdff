#pragma once
// Loading the 2D model configs from YAML (keys = member names; angles in degrees where the key says _deg).
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/steering_motion.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "core/config_node.hpp"

namespace glmbslam::backend {

/// Keys: dt, sigma_v, sigma_omega_deg, euler.
void load_unicycle_motion_config(ConfigNode node, UnicycleMotionConfig& config);
/// Keys: dt, wheel_base, sigma_v, sigma_steer_deg.
void load_steering_motion_config(ConfigNode node, SteeringMotionConfig& config);
/// Keys: sigma_range, sigma_bearing_deg, min_range, max_range, half_fov_deg, p_detect_inside,
/// p_detect_outside, p_survive_inside, p_survive_outside, clutter_rate, clutter_volume.
void load_range_bearing_config(ConfigNode node, RangeBearingConfig& config);

}  // namespace glmbslam::backend
