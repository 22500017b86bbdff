#include "io/kitti_raw.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <system_error>

#include <spdlog/spdlog.h>
#include <Eigen/SVD>

#include "core/error.hpp"
#include "io/kitti_common.hpp"
#include "io/oxts.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::io {

namespace fs = std::filesystem;
using detail::file_line;

namespace {

/// Row-major 3×3 from 9 numbers, checked to be a rotation (tolerance 1e-3: the files hold 7 digits) and
/// projected onto SO(3).
Eigen::Matrix3d rotation_from(const std::vector<double>& v, const std::string& file, const std::string& key) {
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = v[static_cast<std::size_t>(3 * r + c)];
  }
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
      R.determinant() <= 0.0) {
    throw InputError(file, "calibration entry '" + key + "' is not a rotation matrix");
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

Pose3 rigid_from_file(const std::string& path) {
  const detail::KeyValueFile file(path);
  const std::vector<double> R = file.numbers("R", 9);
  const std::vector<double> T = file.numbers("T", 3);
  Pose3 pose = Pose3::Identity();
  pose.linear() = rotation_from(R, path, "R");
  pose.translation() = Eigen::Vector3d(T[0], T[1], T[2]);
  return pose;
}

/// Days since 1970-01-01 of a civil date (proleptic Gregorian; H. Hinnant's algorithm).
long long days_from_civil(long long y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}

}  // namespace

fs::path kitti_raw_date_dir(const std::string& drive_dir) {
  fs::path dir(drive_dir);
  if (!dir.has_filename()) dir = dir.parent_path();
  fs::path parent = dir.parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

KittiRawCalibration read_kitti_raw_calibration(const std::string& date_dir) {
  const fs::path dir(date_dir);
  KittiRawCalibration calib;
  const std::string cam_path = (dir / "calib_cam_to_cam.txt").string();
  const detail::KeyValueFile cam(cam_path);
  const std::vector<double> p0 = cam.numbers("P_rect_00", 12);
  const std::vector<double> p1 = cam.numbers("P_rect_01", 12);
  calib.R_rect_00 = rotation_from(cam.numbers("R_rect_00", 9), cam_path, "R_rect_00");
  calib.stereo.fx = p0[0];
  calib.stereo.fy = p0[5];
  calib.stereo.cx = p0[2];
  calib.stereo.cy = p0[6];
  if (!(calib.stereo.fx > 0.0) || !(calib.stereo.fy > 0.0)) {
    throw InputError(cam_path, "P_rect_00 focal lengths must be positive");
  }
  calib.stereo.baseline = -p1[3] / p1[0];
  if (!(calib.stereo.baseline > 0.0)) {
    throw InputError(cam_path, "P_rect_01[0,3] must be negative (right camera to the right of the left one)");
  }
  calib.T_cam0_velo = rigid_from_file((dir / "calib_velo_to_cam.txt").string());
  calib.T_velo_imu = rigid_from_file((dir / "calib_imu_to_velo.txt").string());
  Pose3 rect = Pose3::Identity();
  rect.linear() = calib.R_rect_00;
  calib.T_cam0_imu = rect * calib.T_cam0_velo * calib.T_velo_imu;
  return calib;
}

std::vector<double> read_kitti_raw_timestamps(const std::string& path) {
  detail::require_file(path, "timestamp file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open timestamp file");
  std::vector<double> times;
  long long s0 = 0;
  double frac0 = 0.0;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (detail::is_blank_line(line)) continue;
    int y = 0, mo = 0, d = 0, h = 0, mi = 0, se = 0, consumed = 0;
    const int got =
        std::sscanf(line.c_str(), "%4d-%2d-%2d %2d:%2d:%2d%n", &y, &mo, &d, &h, &mi, &se, &consumed);
    if (got != 6 || mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || se > 60 || h < 0 || mi < 0 ||
        se < 0) {
      throw InputError(file_line(path, n), "timestamp is not 'YYYY-MM-DD HH:MM:SS.fffffffff'");
    }
    std::string rest = line.substr(static_cast<std::size_t>(consumed));
    rest.erase(rest.find_last_not_of(" \t\r") + 1);
    double frac = 0.0;
    if (!rest.empty()) {
      if (rest[0] != '.' || rest.size() < 2 || rest.find_first_not_of("0123456789", 1) != std::string::npos) {
        throw InputError(file_line(path, n), "timestamp is not 'YYYY-MM-DD HH:MM:SS.fffffffff'");
      }
      frac = std::stod("0" + rest);
    }
    const long long secs = days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d)) * 86400LL +
                           h * 3600LL + mi * 60LL + se;
    if (times.empty()) {
      s0 = secs;
      frac0 = frac;
    }
    const double t = static_cast<double>(secs - s0) + (frac - frac0);
    if (!times.empty() && t <= times.back()) {
      throw InputError(file_line(path, n), "timestamps are not strictly increasing");
    }
    times.push_back(t);
  }
  if (in.bad()) throw InputError(path, "read error");
  if (times.empty()) throw InputError(path, "timestamp file is empty");
  return times;
}

PoseList kitti_raw_ground_truth(const std::string& drive_dir, const KittiRawCalibration& calibration) {
  const std::vector<OxtsRecord> records = read_oxts_folder((fs::path(drive_dir) / "oxts" / "data").string());
  return imu_to_camera_poses(oxts_to_imu_poses(records), calibration.T_cam0_imu);
}

void fill_ground_truth_gaps(PoseList& poses, const std::vector<char>& mask) {
  long last = -1;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (mask[i]) {
      if (last < 0)
        for (std::size_t j = 0; j < i; ++j) poses[j] = poses[i];
      last = static_cast<long>(i);
    } else if (last >= 0) {
      poses[i] = poses[static_cast<std::size_t>(last)];
    }
  }
}

std::optional<PartialGroundTruth> kitti_raw_partial_ground_truth(const std::string& drive_dir,
                                                                 const KittiRawCalibration& calibration,
                                                                 const ImageFileList& left_files) {
  const fs::path data = fs::path(drive_dir) / "oxts" / "data";
  std::vector<OxtsRecord> records;
  std::vector<char> mask(left_files.size(), 0);
  std::size_t missing = 0;
  for (std::size_t i = 0; i < left_files.size(); ++i) {
    const fs::path file = data / (fs::path(left_files.name(i)).stem().string() + ".txt");
    std::error_code ec;
    if (!fs::exists(file, ec)) {
      ++missing;
      continue;
    }
    try {
      records.push_back(read_oxts_file(file.string()));
      mask[i] = 1;
    } catch (const InputError& e) {
      spdlog::warn("ground truth: {} (frame {} left without ground truth)", e.what(), i);
    }
  }
  if (missing > 0)
    spdlog::warn("ground truth: {} has no record for {} of {} frames", data.string(), missing,
                 left_files.size());
  if (records.empty()) return std::nullopt;
  const PoseList measured = imu_to_camera_poses(oxts_to_imu_poses(records), calibration.T_cam0_imu);
  PartialGroundTruth gt;
  gt.poses.assign(left_files.size(), Pose3::Identity());
  std::size_t next = 0;
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) gt.poses[i] = measured[next++];
  fill_ground_truth_gaps(gt.poses, mask);
  if (records.size() < left_files.size()) gt.mask = std::move(mask);
  return gt;
}

KittiRawDataset::KittiRawDataset(const std::string& drive_dir, const std::string& ground_truth_path) {
  const fs::path dir(drive_dir);
  detail::require_directory(dir, "KITTI raw drive folder");
  left_files_ = detail::list_png_files(dir / "image_00" / "data");
  right_files_ = detail::list_png_files(dir / "image_01" / "data");
  detail::require_stereo_pairs(dir, left_files_, right_files_);
  const std::string times_path = (dir / "image_00" / "timestamps.txt").string();
  timestamps_ = read_kitti_raw_timestamps(times_path);
  if (timestamps_.size() != left_files_.size()) {
    throw InputError(times_path, "has " + std::to_string(timestamps_.size()) +
                                     " timestamps but the drive has " + std::to_string(left_files_.size()) +
                                     " stereo images");
  }
  calibration_ = read_kitti_raw_calibration(kitti_raw_date_dir(drive_dir).string());
  detail::fit_calibration_to_image(calibration_.stereo, detail::read_gray_image(left_files_.path(0)),
                                   (kitti_raw_date_dir(drive_dir) / "calib_cam_to_cam.txt").string(),
                                   left_files_.path(0).string());

  std::error_code ec;
  if (!ground_truth_path.empty()) {
    PoseList poses = relative_to_first(read_kitti_poses(ground_truth_path));
    if (poses.size() != left_files_.size()) {
      throw InputError(ground_truth_path, "has " + std::to_string(poses.size()) +
                                              " poses but the drive has " +
                                              std::to_string(left_files_.size()) + " frames");
    }
    ground_truth_ = std::move(poses);
  } else if (fs::is_directory(dir / "oxts", ec)) {
    if (auto gt = kitti_raw_partial_ground_truth(drive_dir, calibration_, left_files_)) {
      ground_truth_ = std::move(gt->poses);
      ground_truth_mask_ = std::move(gt->mask);
    } else {
      spdlog::warn("ground truth: no usable record in {}: running without ground truth",
                   (dir / "oxts" / "data").string());
    }
  }
  const fs::path named = dir.has_filename() ? dir : dir.parent_path();
  name_ = "kitti raw " + named.filename().string();
}

cv::Mat KittiRawDataset::load_image(std::size_t i, StereoSide side) const {
  return detail::read_stereo_image(name_, i, side == StereoSide::kLeft ? left_files_ : right_files_,
                                   calibration_.stereo.width, calibration_.stereo.height);
}

}  // namespace glmbslam::io
