#pragma once
// Trajectory files: KITTI odometry format (12 numbers a line, row-major 3×4 of T_world_camera) and TUM format
// (timestamp tx ty tz qx qy qz qw). Readers validate every line; writers write atomically.
#include <string>
#include <vector>

#include "core/types.hpp"

namespace glmbslam::io {

enum class TrajectoryFormat { kKitti, kTum };

/// Parses "kitti" or "tum"; throws ConfigError otherwise.
TrajectoryFormat parse_trajectory_format(const std::string& name);

/// A trajectory with optional timestamps (empty for KITTI files).
struct Trajectory {
  PoseList poses;
  std::vector<double> timestamps;
};

/// Reads a KITTI pose file. Throws InputError naming the file and line for a line without exactly 12 numbers,
/// a non-finite value, a rotation block that is not a rotation (tolerance 1e-3), or an empty file.
PoseList read_kitti_poses(const std::string& path);

/// Reads a TUM file (comment lines starting with '#' are skipped). Timestamps must increase strictly.
Trajectory read_tum_trajectory(const std::string& path);

/// Reads either format.
Trajectory read_trajectory(const std::string& path, TrajectoryFormat format);

/// One KITTI line for `T` (12 numbers, %.9g, ending in '\n'), as write_kitti_poses writes it.
std::string kitti_pose_line(const Pose3& T);

/// Writes KITTI format with 9 significant digits or more (%.9g), one line per pose; atomic.
void write_kitti_poses(const std::string& path, const PoseList& poses);

/// Writes TUM format; `timestamps` must have the same size as `poses`. Atomic.
void write_tum_trajectory(const std::string& path, const PoseList& poses,
                          const std::vector<double>& timestamps);

/// Expresses every pose relative to the first: T_0^{-1} T_i (KITTI poses start at identity).
PoseList relative_to_first(const PoseList& poses);

}  // namespace glmbslam::io
