#include "io/euroc.hpp"

#include <cmath>
#include <cstdlib>
#include <system_error>

#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "io/kitti_common.hpp"
#include "io/kitti_raw.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::io {

namespace fs = std::filesystem;

namespace {

bool is_camera_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::exists(dir / "data.csv", ec) && fs::exists(dir / "sensor.yaml", ec);
}

}  // namespace

fs::path euroc_mav_dir(const std::string& path) {
  const fs::path dir(path);
  if (is_camera_dir(dir / "mav0" / "cam0") && is_camera_dir(dir / "mav0" / "cam1")) return dir / "mav0";
  if (is_camera_dir(dir / "cam0") && is_camera_dir(dir / "cam1")) return dir;
  return {};
}

std::vector<std::pair<std::size_t, std::size_t>> pair_timestamps(const std::vector<std::int64_t>& left,
                                                                 const std::vector<std::int64_t>& right,
                                                                 std::int64_t tolerance_ns) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  std::size_t i = 0, j = 0;
  while (i < left.size() && j < right.size()) {
    const std::int64_t d = left[i] - right[j];
    if (std::llabs(d) <= tolerance_ns) {
      pairs.emplace_back(i++, j++);
    } else if (d < 0) {
      ++i;
    } else {
      ++j;
    }
  }
  return pairs;
}

std::vector<long> nearest_records(const std::vector<std::int64_t>& frames,
                                  const std::vector<EurocGroundTruthRecord>& records,
                                  std::int64_t tolerance_ns) {
  std::vector<long> out(frames.size(), -1);
  std::size_t j = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    while (j + 1 < records.size() && records[j + 1].timestamp_ns <= frames[i]) ++j;
    long best = -1;
    std::int64_t best_d = tolerance_ns + 1;
    for (std::size_t c = j; c < std::min(records.size(), j + 2); ++c) {
      const std::int64_t d = std::llabs(records[c].timestamp_ns - frames[i]);
      if (d < best_d) {
        best_d = d;
        best = static_cast<long>(c);
      }
    }
    out[i] = best;
  }
  return out;
}

EurocDataset::EurocDataset(const std::string& path, const std::string& ground_truth_path) {
  detail::require_directory(path, "EuRoC folder");
  const fs::path mav = euroc_mav_dir(path);
  if (mav.empty()) {
    // name the first file of the layout that is missing (in mav0/, or in the folder itself when it is mav0)
    const fs::path base =
        fs::is_directory(fs::path(path) / "mav0") ? fs::path(path) / "mav0" : fs::path(path);
    std::string missing;
    for (const char* f : {"cam0/data.csv", "cam0/sensor.yaml", "cam1/data.csv", "cam1/sensor.yaml"}) {
      std::error_code ec;
      if (!fs::exists(base / f, ec)) {
        missing = (base / f).string();
        break;
      }
    }
    throw InputError(path,
                     "not an EuRoC folder (expected mav0/cam0 and mav0/cam1 with data.csv and "
                     "sensor.yaml; missing: " +
                         missing + ")");
  }
  const fs::path cam0 = mav / "cam0", cam1 = mav / "cam1";
  const EurocCameraSensor s0 = read_euroc_sensor_yaml((cam0 / "sensor.yaml").string());
  const EurocCameraSensor s1 = read_euroc_sensor_yaml((cam1 / "sensor.yaml").string());
  rectification_.emplace(s0, s1, (cam1 / "sensor.yaml").string());
  raw_width_ = s0.width;
  raw_height_ = s0.height;

  const std::vector<EurocImageEntry> left = read_euroc_camera_csv((cam0 / "data.csv").string());
  const std::vector<EurocImageEntry> right = read_euroc_camera_csv((cam1 / "data.csv").string());
  std::vector<std::int64_t> tl, tr;
  for (const auto& e : left) tl.push_back(e.timestamp_ns);
  for (const auto& e : right) tr.push_back(e.timestamp_ns);
  const auto pairs = pair_timestamps(tl, tr, euroc_pairing_tolerance_ns);
  if (pairs.empty()) throw InputError((cam1 / "data.csv").string(), "no timestamp matches cam0/data.csv");
  if (pairs.size() < left.size() || pairs.size() < right.size()) {
    spdlog::warn(
        "{}: {} stereo pairs; left images without a right partner dropped: {}, right images without a "
        "left partner dropped: {}",
        mav.string(), pairs.size(), left.size() - pairs.size(), right.size() - pairs.size());
  }
  std::vector<std::int64_t> times_ns;
  left_files_ = ImageFileList(cam0 / "data");
  right_files_ = ImageFileList(cam1 / "data");
  for (const auto& [i, j] : pairs) {
    left_files_.push_back(left[i].filename);
    right_files_.push_back(right[j].filename);
    detail::require_file(left_files_.path(left_files_.size() - 1),
                         "image listed in " + (cam0 / "data.csv").string());
    detail::require_file(right_files_.path(right_files_.size() - 1),
                         "image listed in " + (cam1 / "data.csv").string());
    times_ns.push_back(tl[i]);
    timestamps_.push_back(static_cast<double>(tl[i] - tl.front()) * 1e-9);
  }
  if (!ground_truth_path.empty()) {
    PoseList poses = relative_to_first(read_kitti_poses(ground_truth_path));
    if (poses.size() != size()) {
      throw InputError(ground_truth_path, "has " + std::to_string(poses.size()) +
                                              " poses but the sequence has " + std::to_string(size()) +
                                              " stereo frames");
    }
    ground_truth_ = std::move(poses);
  } else {
    read_ground_truth(mav, times_ns, s0.T_BS);
  }
  const fs::path named = mav.parent_path().has_filename() ? mav.parent_path() : mav;
  name_ = "euroc " + named.filename().string();
}

void EurocDataset::read_ground_truth(const fs::path& mav, const std::vector<std::int64_t>& times_ns,
                                     const Pose3& T_BS) {
  const fs::path file = mav / "state_groundtruth_estimate0" / "data.csv";
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    spdlog::info("{}: no ground truth at {}; --gt FILE evaluates against another file", mav.string(),
                 file.string());
    return;
  }
  std::vector<EurocGroundTruthRecord> records;
  try {
    records = read_euroc_groundtruth_csv(file.string());
  } catch (const InputError& e) {
    spdlog::warn("ground truth ignored: {}", e.what());
    return;
  }
  const auto nearest = nearest_records(
      times_ns, records, static_cast<std::int64_t>(std::llround(euroc_ground_truth_tolerance_s * 1e9)));
  Pose3 T_cam_rect = Pose3::Identity();  // rectified left camera in the unrectified one
  T_cam_rect.linear() = rectification_->rotation_left().transpose();
  PoseList poses(size(), Pose3::Identity());
  std::vector<char> mask(size(), 0);
  std::size_t found = 0;
  for (std::size_t i = 0; i < size(); ++i) {
    if (nearest[i] < 0) continue;
    poses[i] = records[static_cast<std::size_t>(nearest[i])].T_WB * T_BS * T_cam_rect;
    mask[i] = 1;
    ++found;
  }
  if (found == 0) {
    spdlog::warn("{}: no ground-truth record within {} s of any frame: ground truth ignored", file.string(),
                 euroc_ground_truth_tolerance_s);
    return;
  }
  std::size_t first = 0;
  while (!mask[first]) ++first;
  const Pose3 inverse_first = poses[first].inverse();
  for (std::size_t i = 0; i < size(); ++i)
    if (mask[i]) poses[i] = inverse_first * poses[i];
  fill_ground_truth_gaps(poses, mask);
  if (found < size()) {
    spdlog::warn("{}: ground truth for {} of {} frames; evaluation uses those", file.string(), found, size());
    ground_truth_mask_ = std::move(mask);
  }
  ground_truth_ = std::move(poses);
}

cv::Mat EurocDataset::load_image(std::size_t i, StereoSide side) const {
  const bool left = side == StereoSide::kLeft;
  const cv::Mat raw =
      detail::read_stereo_image(name_, i, left ? left_files_ : right_files_, raw_width_, raw_height_);
  return left ? rectification_->rectify_left(raw) : rectification_->rectify_right(raw);
}

}  // namespace glmbslam::io
