#pragma once
// KITTI raw "sync" drive, rectified grayscale stereo:
// DATE/DATE_drive_NNNN_sync/{image_00,image_01}/data/*.png with image_00/timestamps.txt, calibration from the
// date folder (calib_cam_to_cam.txt: P_rect_00, P_rect_01, R_rect_00; calib_velo_to_cam.txt: R, T;
// calib_imu_to_velo.txt: R, T) and ground truth for camera 0 from oxts/data/*.txt (KITTI raw devkit
// convention, relative to frame 0, odometry poses/XX.txt convention).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/image_file_list.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::io {

struct KittiRawCalibration {
  StereoCalibration stereo;  ///< from P_rect_00 / P_rect_01 (width/height 0: they come from the images)
  Pose3 T_cam0_imu;          ///< R_rect_00 · T_cam0_velo · T_velo_imu (rectified camera 0 ← IMU)
  Pose3 T_cam0_velo;         ///< calib_velo_to_cam.txt (unrectified camera 0 ← velodyne)
  Pose3 T_velo_imu;          ///< calib_imu_to_velo.txt (velodyne ← IMU)
  Eigen::Matrix3d R_rect_00 = Eigen::Matrix3d::Identity();
};

/// Reads the three calibration files of a KITTI raw date folder. Throws InputError naming the file and entry.
KittiRawCalibration read_kitti_raw_calibration(const std::string& date_dir);

/// Reads a KITTI raw timestamps.txt ("2011-09-26 13:02:25.964389445" a line), in seconds relative to the
/// first line. Throws InputError naming the file and line for a malformed line or non-increasing timestamps.
std::vector<double> read_kitti_raw_timestamps(const std::string& path);

/// Camera-0 ground truth of a drive folder computed from oxts/data (see oxts.hpp), relative to frame 0.
PoseList kitti_raw_ground_truth(const std::string& drive_dir, const KittiRawCalibration& calibration);

/// Ground truth that may cover only some frames: poses (placeholders where missing) and a per-frame mask.
struct PartialGroundTruth {
  PoseList poses;
  std::vector<char> mask;  ///< 1: measured pose; empty when every frame has one
};

/// Camera-0 ground truth for the given left image files from the oxts record of the same name
/// (oxts/data/<stem>.txt), relative to the first frame that has one. A missing or unreadable record is
/// logged and leaves its frame without ground truth (the nearest measured pose as placeholder). Returns
/// std::nullopt when no frame has a record.
std::optional<PartialGroundTruth> kitti_raw_partial_ground_truth(const std::string& drive_dir,
                                                                 const KittiRawCalibration& calibration,
                                                                 const ImageFileList& left_files);

/// Replaces the poses of frames without ground truth (mask 0) by the nearest earlier measured pose (the first
/// measured one before it).
void fill_ground_truth_gaps(PoseList& poses, const std::vector<char>& mask);

/// The date folder of a drive folder (its parent), tolerant of a trailing slash.
std::filesystem::path kitti_raw_date_dir(const std::string& drive_dir);

class KittiRawDataset : public StereoDataset {
 public:
  /// Opens and validates a drive folder. `ground_truth_path` (a KITTI pose file) overrides the oxts-derived
  /// ground truth (one pose a frame); otherwise it is computed from oxts/ when that folder exists: frames
  /// whose record is missing or broken have no ground truth (logged; see ground_truth_mask).
  explicit KittiRawDataset(const std::string& drive_dir, const std::string& ground_truth_path = "");

  std::size_t size() const override { return left_files_.size(); }
  const StereoCalibration& calibration() const override { return calibration_.stereo; }
  const std::vector<double>& timestamps() const override { return timestamps_; }
  const std::optional<PoseList>& ground_truth() const override { return ground_truth_; }
  const std::vector<char>& ground_truth_mask() const override { return ground_truth_mask_; }
  cv::Mat load_image(std::size_t i, StereoSide side) const override;
  std::string name() const override { return name_; }

  const KittiRawCalibration& raw_calibration() const { return calibration_; }

 private:
  std::string name_;
  KittiRawCalibration calibration_;
  std::vector<double> timestamps_;
  std::optional<PoseList> ground_truth_;
  std::vector<char> ground_truth_mask_;
  ImageFileList left_files_;
  ImageFileList right_files_;
};

}  // namespace glmbslam::io
