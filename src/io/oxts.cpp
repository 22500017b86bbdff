#include "io/oxts.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <system_error>

#include "core/error.hpp"
#include "io/kitti_common.hpp"

namespace glmbslam::io {

namespace fs = std::filesystem;

OxtsRecord read_oxts_file(const std::string& path) {
  detail::require_file(path, "oxts file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open oxts file");
  std::string line;
  std::string content;
  std::size_t lines = 0;
  while (std::getline(in, line)) {
    if (detail::is_blank_line(line)) continue;
    ++lines;
    content = line;
  }
  if (lines == 0) throw InputError(path, "oxts file is empty");
  if (lines > 1) throw InputError(path, "oxts file has " + std::to_string(lines) + " lines, expected 1");
  std::vector<double> v;
  if (!detail::parse_number_list(content, v))
    throw InputError(path, "oxts line contains a token that is not a number");
  if (v.size() != 30) {
    throw InputError(path, "oxts line has " + std::to_string(v.size()) + " values, expected 30");
  }
  for (double x : v) {
    if (!std::isfinite(x)) throw InputError(path, "oxts line contains a non-finite value");
  }
  if (std::abs(v[0]) >= 90.0 || std::abs(v[1]) > 180.0)
    throw InputError(path, "latitude/longitude out of range");
  OxtsRecord r;
  r.lat = v[0];
  r.lon = v[1];
  r.alt = v[2];
  r.roll = v[3];
  r.pitch = v[4];
  r.yaw = v[5];
  return r;
}

std::vector<OxtsRecord> read_oxts_folder(const std::string& data_dir) {
  detail::require_directory(data_dir, "oxts data folder");
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(data_dir, ec)) {
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  }
  if (ec) throw InputError(data_dir, "cannot list oxts data folder (" + ec.message() + ")");
  if (files.empty()) throw InputError(data_dir, "oxts data folder contains no .txt record");
  std::sort(files.begin(), files.end());
  std::vector<OxtsRecord> records;
  records.reserve(files.size());
  for (const auto& f : files) records.push_back(read_oxts_file(f.string()));
  return records;
}

PoseList oxts_to_imu_poses(const std::vector<OxtsRecord>& records) {
  PoseList poses;
  if (records.empty()) return poses;
  constexpr double kEarthRadius = 6378137.0;  // devkit latlonToMercator
  constexpr double pi = 3.14159265358979323846;
  const double scale = std::cos(records.front().lat * pi / 180.0);  // devkit latToScale
  poses.reserve(records.size());
  Pose3 T0_inv = Pose3::Identity();
  for (std::size_t i = 0; i < records.size(); ++i) {
    const OxtsRecord& r = records[i];
    Pose3 T = Pose3::Identity();
    T.translation() =
        Eigen::Vector3d(scale * kEarthRadius * r.lon * pi / 180.0,
                        scale * kEarthRadius * std::log(std::tan((90.0 + r.lat) * pi / 360.0)), r.alt);
    T.linear() = (Eigen::AngleAxisd(r.yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(r.pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(r.roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    if (i == 0) T0_inv = T.inverse();
    poses.push_back(T0_inv * T);
  }
  return poses;
}

PoseList imu_to_camera_poses(const PoseList& imu_poses, const Pose3& T_cam_imu) {
  PoseList out;
  out.reserve(imu_poses.size());
  const Pose3 T_imu_cam = T_cam_imu.inverse();
  for (const auto& T : imu_poses) out.push_back(T_cam_imu * T * T_imu_cam);
  return out;
}

}  // namespace glmbslam::io
