#include "core/error.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::io {

DatasetFormat parse_dataset_format(const std::string& name) {
  if (name == "auto") return DatasetFormat::kAuto;
  if (name == "kitti") return DatasetFormat::kKittiOdometry;
  if (name == "kitti_raw") return DatasetFormat::kKittiRaw;
  if (name == "euroc") return DatasetFormat::kEuroc;
  if (name == "victoria_park") return DatasetFormat::kVictoriaPark;
  throw ConfigError("unknown dataset format '" + name +
                    "' (use auto, kitti, kitti_raw, euroc or victoria_park)");
}

std::string to_string(DatasetFormat format) {
  switch (format) {
    case DatasetFormat::kAuto:
      return "auto";
    case DatasetFormat::kKittiOdometry:
      return "kitti";
    case DatasetFormat::kKittiRaw:
      return "kitti_raw";
    case DatasetFormat::kEuroc:
      return "euroc";
    case DatasetFormat::kVictoriaPark:
      return "victoria_park";
  }
  return "auto";
}

}  // namespace glmbslam::io
