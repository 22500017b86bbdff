// detect_dataset_format and open_stereo_dataset (declared in io/stereo_dataset.hpp).
#include <filesystem>
#include <system_error>

#include "core/error.hpp"
#include "io/euroc.hpp"
#include "io/kitti_odometry.hpp"
#include "io/kitti_raw.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::io {

namespace fs = std::filesystem;

DatasetFormat detect_dataset_format(const std::string& path) {
  const fs::path dir(path);
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw InputError(path, "dataset folder not found");
  if (!fs::is_directory(dir, ec)) throw InputError(path, "dataset path is not a folder");
  if (fs::is_directory(dir / "image_0", ec) && fs::exists(dir / "calib.txt", ec)) {
    return DatasetFormat::kKittiOdometry;
  }
  if (fs::is_directory(dir / "image_00", ec) && fs::is_directory(dir / "image_01", ec)) {
    return DatasetFormat::kKittiRaw;
  }
  // a mav0/ folder is EuRoC even when incomplete: its reader then names the missing file
  if (!euroc_mav_dir(path).empty() || fs::is_directory(dir / "mav0", ec)) return DatasetFormat::kEuroc;
  if (fs::exists(dir / "aa3_dr.mat", ec)) return DatasetFormat::kVictoriaPark;
  throw InputError(
      path,
      "unknown dataset layout (expected a KITTI odometry sequence folder with image_0/ and calib.txt, "
      "a KITTI raw drive folder with image_00/ and image_01/, an EuRoC folder holding mav0/ (or mav0 "
      "itself), "
      "or a Victoria Park folder with aa3_dr.mat)");
}

std::unique_ptr<StereoDataset> open_stereo_dataset(const std::string& path, DatasetFormat format,
                                                   const std::string& ground_truth_path) {
  if (format == DatasetFormat::kAuto) format = detect_dataset_format(path);
  switch (format) {
    case DatasetFormat::kKittiOdometry:
      return std::make_unique<KittiOdometryDataset>(path, ground_truth_path);
    case DatasetFormat::kKittiRaw:
      return std::make_unique<KittiRawDataset>(path, ground_truth_path);
    case DatasetFormat::kEuroc:
      return std::make_unique<EurocDataset>(path, ground_truth_path);
    case DatasetFormat::kVictoriaPark:
      throw InputError(path, "is a Victoria Park dataset (2D range-bearing), not a stereo dataset");
    case DatasetFormat::kAuto:
      break;
  }
  throw InputError(path, "cannot determine the dataset format");
}

}  // namespace glmbslam::io
