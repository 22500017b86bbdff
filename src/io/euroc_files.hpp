#pragma once
// Parsers of the EuRoC MAV ASL dataset files (mav0/<sensor>/...): each takes a path, validates every entry
// and throws InputError naming the file (and line) and the problem.
//   cam0/data.csv                      "#timestamp [ns],filename" then "<ns>,<ns>.png" a line
//   cam0/sensor.yaml                   %YAML:1.0 header, T_BS (4×4, row-major), intrinsics [fu, fv, cu, cv],
//                                      radial-tangential distortion [k1, k2, p1, p2], resolution [w, h]
//   state_groundtruth_estimate0/data.csv  "<ns>, px, py, pz, qw, qx, qy, qz[, …]" (≥ 8 columns, body frame)
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace glmbslam::io {

/// One line of a camera's data.csv.
struct EurocImageEntry {
  std::int64_t timestamp_ns = 0;
  std::string filename;  ///< relative to the camera's data/ folder
};

/// A camera's sensor.yaml.
struct EurocCameraSensor {
  Pose3 T_BS = Pose3::Identity();  ///< sensor (camera) frame expressed in the body frame
  double fu = 0.0, fv = 0.0, cu = 0.0, cv = 0.0;
  std::vector<double> distortion;  ///< radial-tangential k1, k2, p1, p2
  int width = 0, height = 0;
  double rate_hz = 0.0;  ///< 0 when absent
};

/// One ground-truth state: the body pose in the world frame.
struct EurocGroundTruthRecord {
  std::int64_t timestamp_ns = 0;
  Pose3 T_WB = Pose3::Identity();
};

/// Reads a camera data.csv: timestamps strictly increasing, file names non-empty. An empty list is an error.
std::vector<EurocImageEntry> read_euroc_camera_csv(const std::string& path);

/// Reads a camera sensor.yaml (the `%YAML:1.0` header line is accepted). Requires camera_model pinhole,
/// distortion_model radial-tangential, positive focal lengths and resolution, T_BS a rigid transform.
EurocCameraSensor read_euroc_sensor_yaml(const std::string& path);

/// Reads state_groundtruth_estimate0/data.csv (columns beyond the first 8 are ignored). Timestamps strictly
/// increasing, quaternions of non-zero norm (normalised), every value finite. An empty list is an error.
std::vector<EurocGroundTruthRecord> read_euroc_groundtruth_csv(const std::string& path);

}  // namespace glmbslam::io
