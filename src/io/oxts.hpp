#pragma once
// KITTI raw OXTS (GPS/IMU) records and their conversion to poses, exactly as the KITTI raw devkit does it
// (convertOxtsToPose.m): Mercator projection with scale = cos(lat₀·π/180), earth radius 6378137 m,
// t = (s·er·lon·π/180, s·er·ln(tan((90+lat)·π/360)), alt), R = Rz(yaw)·Ry(pitch)·Rx(roll).
#include <string>
#include <vector>

#include "core/types.hpp"

namespace glmbslam::io {

/// The first six of the 30 values of an oxts/data/*.txt line (see oxts/dataformat.txt).
struct OxtsRecord {
  double lat = 0.0;    ///< latitude [deg]
  double lon = 0.0;    ///< longitude [deg]
  double alt = 0.0;    ///< altitude [m]
  double roll = 0.0;   ///< [rad]
  double pitch = 0.0;  ///< [rad]
  double yaw = 0.0;    ///< heading [rad], 0 = east
};

/// Reads one oxts file (a single line of exactly 30 finite numbers). Throws InputError naming the file.
OxtsRecord read_oxts_file(const std::string& path);

/// Reads every oxts/data/*.txt file of a folder in name order. Throws InputError naming the folder if it is
/// missing or empty.
std::vector<OxtsRecord> read_oxts_folder(const std::string& data_dir);

/// T_world_imu for every record, in the devkit's Mercator frame (scale from the first record's latitude),
/// expressed relative to the first record (first pose = identity), as convertOxtsToPose.m returns them.
PoseList oxts_to_imu_poses(const std::vector<OxtsRecord>& records);

/// Camera poses relative to frame 0 (odometry poses/XX.txt convention) from IMU poses relative to frame 0:
/// pose_i = T_cam_imu · T_imu0_imui · T_cam_imu⁻¹.
PoseList imu_to_camera_poses(const PoseList& imu_poses, const Pose3& T_cam_imu);

}  // namespace glmbslam::io
