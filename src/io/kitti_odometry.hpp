#pragma once
// KITTI odometry stereo sequence: sequences/XX/{image_0,image_1}/NNNNNN.png, calib.txt (P0..P3, 12 numbers
// each), times.txt, and ground truth poses/XX.txt (found at ../../poses/XX.txt or given explicitly).
// Frames are read lazily, one image per load_image(i, side).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/image_file_list.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::io {

/// Reads calib.txt: fx, fy, cx, cy from P0, baseline = −P1[0,3]/fx (must be > 0). Every line must hold
/// exactly 12 finite numbers. Width and height are left at 0 (they come from the images).
StereoCalibration read_kitti_odometry_calibration(const std::string& calib_path);

/// Reads times.txt (one finite number a line, strictly increasing), returned relative to the first.
std::vector<double> read_kitti_times(const std::string& times_path);

/// The ground-truth file of the standard layout for a sequence folder (…/sequences/XX → …/poses/XX.txt),
/// or an empty string if there is none.
std::string find_kitti_ground_truth(const std::string& sequence_dir);

class KittiOdometryDataset : public StereoDataset {
 public:
  /// Opens and validates the sequence folder (see file comment). `ground_truth_path` overrides the standard
  /// location; when given, it must exist. Ground truth must have one pose per frame.
  explicit KittiOdometryDataset(const std::string& sequence_dir, const std::string& ground_truth_path = "");

  std::size_t size() const override { return left_files_.size(); }
  const StereoCalibration& calibration() const override { return calibration_; }
  const std::vector<double>& timestamps() const override { return timestamps_; }
  const std::optional<PoseList>& ground_truth() const override { return ground_truth_; }
  cv::Mat load_image(std::size_t i, StereoSide side) const override;
  std::string name() const override { return name_; }

  /// Path of the ground-truth file actually read (empty if none).
  const std::string& ground_truth_path() const { return ground_truth_path_; }

 private:
  std::string name_;
  StereoCalibration calibration_;
  std::vector<double> timestamps_;
  std::optional<PoseList> ground_truth_;
  std::string ground_truth_path_;
  ImageFileList left_files_;
  ImageFileList right_files_;
};

}  // namespace glmbslam::io
