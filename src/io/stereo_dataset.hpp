#pragma once
// A rectified stereo sequence read lazily, frame by frame (a long sequence is never loaded at once).
// Implementations: KITTI odometry (sequences/XX), KITTI raw (DATE/DATE_drive_NNNN_sync) and EuRoC ASL
// (mav0/).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/types.hpp"

namespace glmbslam::io {

/// One stereo pair: 8-bit grayscale, rectified.
struct StereoFrame {
  std::size_t index = 0;
  double timestamp = 0.0;  ///< seconds from the start of the sequence
  cv::Mat left;
  cv::Mat right;
};

/// Which image of a stereo pair.
enum class StereoSide { kLeft, kRight };

enum class DatasetFormat { kAuto, kKittiOdometry, kKittiRaw, kEuroc, kVictoriaPark };

/// Parses "auto", "kitti", "kitti_raw", "euroc", "victoria_park"; throws ConfigError otherwise.
DatasetFormat parse_dataset_format(const std::string& name);
std::string to_string(DatasetFormat format);

class StereoDataset {
 public:
  virtual ~StereoDataset() = default;
  /// Number of stereo frames.
  virtual std::size_t size() const = 0;
  /// Rectified calibration (left camera intrinsics, baseline, image size).
  virtual const StereoCalibration& calibration() const = 0;
  /// Timestamps in seconds, one per frame, strictly increasing.
  virtual const std::vector<double>& timestamps() const = 0;
  /// Ground-truth poses T_world_cam0 relative to frame 0 (one per frame), if available. Frames without a
  /// measured pose (see ground_truth_mask) hold the nearest measured one as a placeholder.
  virtual const std::optional<PoseList>& ground_truth() const = 0;
  /// Per frame: 1 if ground_truth() holds a measured pose for it, 0 for a placeholder. Empty: every frame has
  /// one. Evaluation uses the frames marked 1 only.
  virtual const std::vector<char>& ground_truth_mask() const {
    static const std::vector<char> all;
    return all;
  }
  /// One image of frame i (0 ≤ i < size()), rectified. Throws InputError naming the dataset if i is out of
  /// range, or naming the image file if it is missing or unreadable, or if its size does not match the
  /// calibration. Safe to call for the two sides of a frame concurrently (the pipeline decodes them in
  /// parallel).
  virtual cv::Mat load_image(std::size_t i, StereoSide side) const = 0;
  /// Loads frame i: its timestamp and both images (load_image of each side, one after the other).
  StereoFrame load(std::size_t i) const;
  /// Human-readable name (e.g. "kitti odometry 00").
  virtual std::string name() const = 0;
};

/// Detects the format of `path` (a folder): a KITTI odometry sequence folder (with image_0/ image_1/
/// calib.txt), a KITTI raw drive folder (with image_00/ image_01/), an EuRoC ASL folder (holding mav0/, or
/// mav0 itself with cam0/ cam1/), or a Victoria Park folder (aa3_dr.mat).
/// Throws InputError naming the path if it matches none.
DatasetFormat detect_dataset_format(const std::string& path);

/// Opens a stereo dataset. `ground_truth_path` overrides where the ground-truth poses are read from.
/// Throws InputError for a missing folder, mismatched left/right image counts, bad calibration, etc.
std::unique_ptr<StereoDataset> open_stereo_dataset(const std::string& path,
                                                   DatasetFormat format = DatasetFormat::kAuto,
                                                   const std::string& ground_truth_path = "");

}  // namespace glmbslam::io
