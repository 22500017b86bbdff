#pragma once
// Stage 3 of the stereo pipeline (filter): chooses the measurements handed to the backend, forms the
// control from the VO and runs one step of the particle filter chosen by pipeline.algorithm — δ-GLMB-SLAM
// (glmb2 / glmb1) or LMB-SLAM (lmb / lmb1). Later stages see the filter only through this class.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "app/measurement_selection.hpp"
#include "app/pipeline/frame_source.hpp"
#include "app/stereo_config.hpp"
#include "backend/glmb/glmb_map.hpp"
#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "frontend/visual_odometry.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::app {

/// A measurement set handed to the stereo backend.
using StereoMeasurementSet =
    std::vector<backend::StereoMeasurementModel::Measurement,
                Eigen::aligned_allocator<backend::StereoMeasurementModel::Measurement>>;

/// The filter's state after a step, whatever the algorithm (what the pipeline logs and records).
struct FilterStatus {
  int tracks = 0;      ///< tracks (labels) held by the best particle
  int hypotheses = 0;  ///< map hypotheses of the best particle (1 for a single-hypothesis map)
  double ess = 0.0;    ///< effective sample size after the weight update (before resampling)
  bool resampled = false;
};

/// What the filter stage did with one frame.
struct FilterStep {
  StereoMeasurementSet Z;  ///< the measurements handed to the backend
  /// Index into the frame's StereoFrameFeatures::measurements of each element of Z.
  std::vector<int> selected;
  backend::RelativePoseControl control;  ///< u_k, Q_k given to the backend (unused at k = 0)
  /// The camera saw nothing (no images, or too few stereo measurements for the VO): the backend moved its
  /// poses with the control and left its map (blind_step), and Z is empty. The VO's reference, and with it
  /// the selection the next frame's tracked features refer to, stays at the last frame that saw.
  bool blind = false;
  double ms = 0.0;  ///< backend wall time
};

/// The particle filter behind the stage (filter_stage.cpp: δ-GLMB-SLAM or LMB-SLAM).
class StereoBackend;

class FilterStage {
 public:
  /// The backend follows config.pipeline.algorithm: glmb2 / glmb1 (δ-GLMB-SLAM) or lmb / lmb1 (LMB-SLAM),
  /// with config.rbpf (its proposal set by the caller) and, for LMB-SLAM, config.lmb.
  FilterStage(const StereoConfig& config, const StereoCalibration& calibration);
  ~FilterStage();
  FilterStage(const FilterStage&) = delete;
  FilterStage& operator=(const FilterStage&) = delete;

  /// Frame k of the run: k = 0 is the initial scan at the known initial pose, then one filter step each.
  const FilterStep& step(const FrameWork& work, const frontend::VoEstimate& vo_estimate,
                         const frontend::StereoVisualOdometry& vo, std::size_t k);

  const FilterStep& last_step() const { return step_; }
  /// The pose estimate at the last step (the best particle's).
  Pose3 pose() const;
  FilterStatus status() const;
  /// The estimated trajectory, steps 0..k (pipeline.trajectory_estimate: the sampled poses or the
  /// Rao–Blackwellised estimates of the best particle).
  PoseList trajectory() const;
  /// The landmarks of the final MAP estimate, as PCD points.
  std::vector<io::MapPoint> map_points() const;

 private:
  const StereoConfig& config_;
  backend::Se3Motion motion_;
  backend::StereoMeasurementModel model_;
  std::unique_ptr<StereoBackend> filter_;
  SelectionRules rules_;
  SelectionGrid grid_;
  std::vector<char> previous_selected_;  // per measurement of the previous frame: handed to the backend
  FilterStep step_;
};

/// Labels (birth step, index) packed into one integer for the PCD map: birth step << 12 | index.
std::uint64_t pack_label(const backend::Label& label);
/// The birth step of a label packed by pack_label.
inline std::size_t label_birth_step(std::uint64_t packed) {
  return static_cast<std::size_t>(packed >> 12);
}

}  // namespace glmbslam::app
