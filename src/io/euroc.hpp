#pragma once
// EuRoC MAV dataset in the ASL layout: mav0/{cam0,cam1}/{data.csv,sensor.yaml,data/<ns>.png} and, when
// present, mav0/state_groundtruth_estimate0/data.csv. The raw images are undistorted and rectified with a
// map computed once from the two sensor.yaml files (stereo_rectification.hpp). Ground truth is the body pose
// nearest in time (within euroc_ground_truth_tolerance_s) times T_BS(cam0) and the rectification, expressed
// like KITTI's: relative to the first frame that has ground truth, rectified left camera.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/euroc_files.hpp"
#include "io/image_file_list.hpp"
#include "io/stereo_dataset.hpp"
#include "io/stereo_rectification.hpp"

namespace glmbslam::io {

/// Largest time difference between a frame and the ground-truth record assigned to it.
inline constexpr double euroc_ground_truth_tolerance_s = 0.02;
/// Largest time difference between a left and a right image paired into one stereo frame.
inline constexpr std::int64_t euroc_pairing_tolerance_ns = 1'000'000;

/// The mav0 folder of `path` (path/mav0, or path itself when it holds cam0/ and cam1/ with data.csv), or an
/// empty path when it is not an EuRoC folder.
std::filesystem::path euroc_mav_dir(const std::string& path);

/// Pairs two increasing timestamp lists: (left index, right index) of each pair within `tolerance_ns`.
std::vector<std::pair<std::size_t, std::size_t>> pair_timestamps(const std::vector<std::int64_t>& left,
                                                                 const std::vector<std::int64_t>& right,
                                                                 std::int64_t tolerance_ns);

/// Per frame time, the index of the nearest ground-truth record within `tolerance_ns`, or −1.
std::vector<long> nearest_records(const std::vector<std::int64_t>& frames,
                                  const std::vector<EurocGroundTruthRecord>& records,
                                  std::int64_t tolerance_ns);

class EurocDataset : public StereoDataset {
 public:
  /// Opens and validates an EuRoC folder (holding mav0/, or mav0 itself). `ground_truth_path` (a KITTI pose
  /// file, one pose a frame) overrides state_groundtruth_estimate0. A broken ground-truth file is logged and
  /// ignored (the images still run).
  explicit EurocDataset(const std::string& path, const std::string& ground_truth_path = "");

  std::size_t size() const override { return left_files_.size(); }
  const StereoCalibration& calibration() const override { return rectification_->calibration(); }
  const std::vector<double>& timestamps() const override { return timestamps_; }
  const std::optional<PoseList>& ground_truth() const override { return ground_truth_; }
  const std::vector<char>& ground_truth_mask() const override { return ground_truth_mask_; }
  cv::Mat load_image(std::size_t i, StereoSide side) const override;
  std::string name() const override { return name_; }

 private:
  void read_ground_truth(const std::filesystem::path& mav, const std::vector<std::int64_t>& times_ns,
                         const Pose3& T_BS);

  std::string name_;
  std::optional<StereoRectification> rectification_;
  std::vector<double> timestamps_;
  std::optional<PoseList> ground_truth_;
  std::vector<char> ground_truth_mask_;
  ImageFileList left_files_;
  ImageFileList right_files_;
  int raw_width_ = 0, raw_height_ = 0;
};

}  // namespace glmbslam::io
