#pragma once
// The built-in drive rendered when `glmbslam render` gets no --poses: a car-like loop of about 400 m around a
// 130 m × 80 m block (four 90° right turns of 15 m radius with smooth curvature ramps), 9.5 m/s on the
// straights and 7 m/s in the turns, gentle ±1 m height undulation, then 40 m more along the first straight so
// the start is seen again (a loop closure). Poses are KITTI camera frames (x right, y down, z forward) at 10
// Hz, the first one the identity.
#include "core/types.hpp"

namespace glmbslam::sim {

struct DefaultTrajectoryInfo {
  double loop_length = 0.0;   ///< metres of the closed loop
  double total_length = 0.0;  ///< metres driven (loop + overlap)
};

/// Poses at `rate_hz` (10 Hz for KITTI timing).
PoseList default_trajectory(double rate_hz = 10.0, DefaultTrajectoryInfo* info = nullptr);

}  // namespace glmbslam::sim
