#pragma once
// Landmark maps as PCD files (through PCL), readable by pcl_viewer and pcl::io::loadPCDFile.
// Fields: x y z (float32), label (uint32, PCL's "label" convention so pcl_viewer can colour by it),
// existence (float32, the landmark's existence probability). Binary by default, ASCII on request.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::io {

struct MapPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  std::uint64_t label = 0;  ///< must fit in 32 bits (stored as uint32)
  double existence = 0.0;   ///< in [0, 1]
};

/// Writes the map atomically (temporary name, then rename). Throws InputError naming `path` if a position or
/// existence is non-finite, an existence is outside [0, 1], a label does not fit in 32 bits, or writing
/// fails. An empty map is written as a valid PCD with 0 points.
void write_pcd_map(const std::string& path, const std::vector<MapPoint>& points, bool binary = true);

/// Reads a map written by write_pcd_map (or any PCD with x y z label existence). Throws InputError naming the
/// file if it is missing, unreadable or lacks one of those fields.
std::vector<MapPoint> read_pcd_map(const std::string& path);

}  // namespace glmbslam::io
