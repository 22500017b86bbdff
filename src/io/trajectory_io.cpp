#include "io/trajectory_io.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/kitti_common.hpp"

namespace glmbslam::io {
namespace {

using detail::is_blank_line;
using detail::parse_number_list;

std::string where(const std::string& path, std::size_t line) {
  return detail::file_line(path, line);
}

}  // namespace

TrajectoryFormat parse_trajectory_format(const std::string& name) {
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "tum") return TrajectoryFormat::kTum;
  throw ConfigError("unknown trajectory format '" + name + "' (use kitti or tum)");
}

PoseList read_kitti_poses(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open pose file");
  PoseList poses;
  std::string line;
  std::vector<double> v;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (is_blank_line(line)) continue;
    if (!parse_number_list(line, v))
      throw InputError(where(path, n), "pose line contains a token that is not a number");
    if (v.size() != 12) {
      throw InputError(where(path, n), "pose line has " + std::to_string(v.size()) + " numbers, expected 12");
    }
    for (double x : v) {
      if (!std::isfinite(x)) throw InputError(where(path, n), "pose line contains a non-finite value");
    }
    Pose3 T = Pose3::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) T.matrix()(r, c) = v[static_cast<std::size_t>(4 * r + c)];
    }
    const Eigen::Matrix3d R = T.linear();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
        R.determinant() < 0.0) {
      throw InputError(where(path, n), "rotation block is not a rotation matrix");
    }
    poses.push_back(T);
  }
  if (in.bad()) throw InputError(path, "read error");
  if (poses.empty()) throw InputError(path, "pose file is empty");
  return poses;
}

Trajectory read_tum_trajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open trajectory file");
  Trajectory traj;
  std::string line;
  std::vector<double> v;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (is_blank_line(line) || line[line.find_first_not_of(" \t")] == '#') continue;
    if (!parse_number_list(line, v))
      throw InputError(where(path, n), "line contains a token that is not a number");
    if (v.size() != 8) {
      throw InputError(where(path, n), "TUM line has " + std::to_string(v.size()) + " numbers, expected 8");
    }
    for (double x : v) {
      if (!std::isfinite(x)) throw InputError(where(path, n), "line contains a non-finite value");
    }
    if (!traj.timestamps.empty() && v[0] <= traj.timestamps.back()) {
      throw InputError(where(path, n), "timestamps are not strictly increasing");
    }
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3) throw InputError(where(path, n), "quaternion is not unit length");
    q.normalize();
    Pose3 T = Pose3::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    traj.poses.push_back(T);
    traj.timestamps.push_back(v[0]);
  }
  if (in.bad()) throw InputError(path, "read error");
  if (traj.poses.empty()) throw InputError(path, "trajectory file is empty");
  return traj;
}

Trajectory read_trajectory(const std::string& path, TrajectoryFormat format) {
  if (format == TrajectoryFormat::kTum) return read_tum_trajectory(path);
  Trajectory t;
  t.poses = read_kitti_poses(path);
  return t;
}

namespace {

/// Writers refuse what the readers would reject, so every file written can be read back.
void check_finite_poses(const std::string& path, const PoseList& poses) {
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!poses[i].matrix().allFinite()) {
      throw InputError(path, "cannot write trajectory: pose " + std::to_string(i) + " is not finite");
    }
  }
}

}  // namespace

std::string kitti_pose_line(const Pose3& T) {
  std::string line;
  char buf[64];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof buf, "%.9g", T.matrix()(r, c));
      line += buf;
      line += (r == 2 && c == 3) ? '\n' : ' ';
    }
  }
  return line;
}

void write_kitti_poses(const std::string& path, const PoseList& poses) {
  check_finite_poses(path, poses);
  write_text_file_atomically(path, [&](std::ostream& out) {
    for (const auto& T : poses) out << kitti_pose_line(T);
  });
}

void write_tum_trajectory(const std::string& path, const PoseList& poses,
                          const std::vector<double>& timestamps) {
  if (timestamps.size() != poses.size()) {
    throw InputError(path, "cannot write TUM trajectory: " + std::to_string(poses.size()) + " poses but " +
                               std::to_string(timestamps.size()) + " timestamps");
  }
  check_finite_poses(path, poses);
  for (std::size_t i = 0; i < timestamps.size(); ++i) {
    if (!std::isfinite(timestamps[i])) {
      throw InputError(path,
                       "cannot write TUM trajectory: timestamp " + std::to_string(i) + " is not finite");
    }
    if (i > 0 && timestamps[i] <= timestamps[i - 1]) {
      throw InputError(path, "cannot write TUM trajectory: timestamps are not strictly increasing at pose " +
                                 std::to_string(i));
    }
  }
  write_text_file_atomically(path, [&](std::ostream& out) {
    char buf[256];
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Eigen::Quaterniond q(poses[i].linear());
      const Eigen::Vector3d t = poses[i].translation();
      std::snprintf(buf, sizeof buf, "%.9f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", timestamps[i], t.x(), t.y(),
                    t.z(), q.x(), q.y(), q.z(), q.w());
      out << buf;
    }
  });
}

PoseList relative_to_first(const PoseList& poses) {
  PoseList out;
  out.reserve(poses.size());
  if (poses.empty()) return out;
  const Pose3 inv0 = poses.front().inverse();
  for (const auto& T : poses) out.push_back(inv0 * T);
  return out;
}

}  // namespace glmbslam::io
