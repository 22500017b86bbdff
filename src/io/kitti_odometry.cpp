#include "io/kitti_odometry.hpp"

#include <cmath>
#include <fstream>
#include <system_error>

#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "io/kitti_common.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::io {

namespace fs = std::filesystem;
using detail::file_line;

StereoCalibration read_kitti_odometry_calibration(const std::string& calib_path) {
  const detail::KeyValueFile file(calib_path);
  for (const auto& key : file.keys()) file.numbers(key, 12);  // every line: 12 finite numbers
  const std::vector<double> p0 = file.numbers("P0", 12);
  const std::vector<double> p1 = file.numbers("P1", 12);
  StereoCalibration calib;
  calib.fx = p0[0];
  calib.fy = p0[5];
  calib.cx = p0[2];
  calib.cy = p0[6];
  if (!(calib.fx > 0.0) || !(calib.fy > 0.0))
    throw InputError(calib_path, "P0 focal lengths must be positive");
  calib.baseline = -p1[3] / p1[0];
  if (!(calib.baseline > 0.0)) {
    throw InputError(calib_path, "P1[0,3] must be negative (right camera to the right of the left one)");
  }
  return calib;
}

std::vector<double> read_kitti_times(const std::string& times_path) {
  detail::require_file(times_path, "timestamp file");
  std::ifstream in(times_path);
  if (!in) throw InputError(times_path, "cannot open timestamp file");
  std::vector<double> times;
  std::vector<double> v;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (detail::is_blank_line(line)) continue;
    if (!detail::parse_number_list(line, v) || v.size() != 1) {
      throw InputError(file_line(times_path, n), "timestamp line must hold exactly one number");
    }
    if (!std::isfinite(v[0])) throw InputError(file_line(times_path, n), "timestamp is not finite");
    if (!times.empty() && v[0] <= times.back()) {
      throw InputError(file_line(times_path, n), "timestamps are not strictly increasing");
    }
    times.push_back(v[0]);
  }
  if (in.bad()) throw InputError(times_path, "read error");
  if (times.empty()) throw InputError(times_path, "timestamp file is empty");
  const double t0 = times.front();
  for (double& t : times) t -= t0;
  return times;
}

namespace {

/// …/sequences/XX → …/poses/XX.txt of the path as given (empty if it names no folder).
fs::path ground_truth_beside(fs::path dir) {
  if (!dir.has_filename()) dir = dir.parent_path();  // trailing slash
  const std::string seq = dir.filename().string();
  if (seq.empty()) return {};
  return dir.parent_path().parent_path() / "poses" / (seq + ".txt");
}

}  // namespace

std::string find_kitti_ground_truth(const std::string& sequence_dir) {
  // the path as given, then with its symbolic links resolved (a link to sequences/XX elsewhere)
  std::error_code ec;
  const fs::path given = ground_truth_beside(sequence_dir);
  if (!given.empty() && fs::is_regular_file(given, ec)) return given.string();
  const fs::path real = fs::canonical(sequence_dir, ec);
  if (ec) return "";
  const fs::path resolved = ground_truth_beside(real);
  return !resolved.empty() && fs::is_regular_file(resolved, ec) ? resolved.string() : std::string();
}

KittiOdometryDataset::KittiOdometryDataset(const std::string& sequence_dir,
                                           const std::string& ground_truth_path) {
  const fs::path dir(sequence_dir);
  detail::require_directory(dir, "KITTI odometry sequence folder");
  left_files_ = detail::list_png_files(dir / "image_0");
  right_files_ = detail::list_png_files(dir / "image_1");
  detail::require_stereo_pairs(dir, left_files_, right_files_);
  calibration_ = read_kitti_odometry_calibration((dir / "calib.txt").string());
  const std::string times_path = (dir / "times.txt").string();
  timestamps_ = read_kitti_times(times_path);
  if (timestamps_.size() != left_files_.size()) {
    throw InputError(times_path, "has " + std::to_string(timestamps_.size()) +
                                     " timestamps but the sequence has " +
                                     std::to_string(left_files_.size()) + " stereo images");
  }
  detail::fit_calibration_to_image(calibration_, detail::read_gray_image(left_files_.path(0)),
                                   (dir / "calib.txt").string(), left_files_.path(0).string());

  ground_truth_path_ = ground_truth_path.empty() ? find_kitti_ground_truth(sequence_dir) : ground_truth_path;
  if (!ground_truth_path_.empty()) {
    PoseList poses = read_kitti_poses(ground_truth_path_);
    if (poses.size() != left_files_.size()) {
      throw InputError(ground_truth_path_, "has " + std::to_string(poses.size()) +
                                               " poses but the sequence has " +
                                               std::to_string(left_files_.size()) + " frames");
    }
    ground_truth_ = relative_to_first(poses);
  } else {
    spdlog::info("{}: no ground truth at {} (the KITTI layout); --gt FILE evaluates against another file",
                 sequence_dir, ground_truth_beside(sequence_dir).string());
  }
  fs::path named = dir.has_filename() ? dir : dir.parent_path();
  name_ = "kitti odometry " + named.filename().string();
}

cv::Mat KittiOdometryDataset::load_image(std::size_t i, StereoSide side) const {
  return detail::read_stereo_image(name_, i, side == StereoSide::kLeft ? left_files_ : right_files_,
                                   calibration_.width, calibration_.height);
}

}  // namespace glmbslam::io
