#pragma once
// Refinement of the stereo filter by RFS maximum-likelihood SLAM (paper 004;
// backend/mlslam/stereo_ml_slam.hpp), `glmbslam run --refine ml`: the trajectory and the landmark set are
// re-estimated with the associations summed out (Eq. 7–8), from the filter's estimate, with the VO controls
// and their covariance Q as the motion factors and the measurement sets the filter was given.
//   online: every `refine.every` frames, the last `refine.window` frames are solved with their first pose
//   held
//           (older poses fixed); the landmarks start from the filter's current map, moved into the refined
//           frame by the correction at the window's first pose; frames not yet refined follow the filter's
//           motion from the last refined pose.
//   final:  one solve over the whole run (`refine.final`; skipped when the run was interrupted, stopped at
//           its next EM round when an interruption comes during it) from the windows' trajectory, each
//           landmark of the filter's final map moved with the refinement of the frame that mapped it
//           (`refine.final_start: windows`), or from the filter's final trajectory and map (`filter`). With
//           measurement.pixel_sigma auto its σ is the median of the σ the filter used frame by frame (the
//           frames whose σ was an estimate, not the initial value before enough residuals): the
//           last frame's σ describes only the last 100 moving frames (on rendered KITTI 08, 1.28 px after a
//           hard last stretch against a median of 0.64 px, which widened every gate of the pass and made its
//           t_rel 0.257 % against 0.201 % with the median).
// The stage uses only what the pipeline hands every stage (FrameOutcome): the filter's pose, trajectory, map
// and its measurement sets and controls.
#include <functional>
#include <optional>
#include <vector>

#include "app/pipeline/loop_closing.hpp"
#include "app/pipeline/pipeline_stage.hpp"
#include "app/stereo_config.hpp"
#include "backend/mlslam/stereo_batch_ml_slam.hpp"
#include "backend/mlslam/stereo_ml_slam.hpp"

namespace glmbslam::app {

class RefinementStage : public PipelineStage {
 public:
  /// `config.refine` holds the settings; the config must outlive the stage. `stop` (may be empty) is asked
  /// before every EM round of the final pass: when it says true (an interrupted run) the pass ends with its
  /// last completed round's estimate and the record is marked interrupted.
  RefinementStage(const StereoConfig& config, const StereoCalibration& calibration,
                  std::function<bool()> stop = {});

  void on_frame(const FrameOutcome& frame) override;
  /// Sets record.refined_poses, record.refined_map and record.refinement (timings and solver counters).
  void on_finish(RunRecord& record) override;

  /// The refined trajectory so far, one pose per frame (frames after the last window follow the filter).
  const PoseList& trajectory() const { return refined_; }

 private:
  void solve_window(std::size_t last, const std::vector<io::MapPoint>& filter_map);

  const RefineSettings& settings_;
  backend::Se3Motion motion_;
  backend::StereoMeasurementModel model_;
  bool automatic_pixel_sigma_;  ///< measurement.pixel_sigma auto: follow the filter's σ
  /// measurement.pixel_sigma auto: the filter's σ at each frame where it was an estimate (the final pass
  /// takes their median)
  std::vector<double> pixel_sigmas_;
  backend::StereoMlSlam window_solver_, final_solver_;
  std::optional<LoopClosing> loop_closing_;  ///< refine.loop_closure
  /// The final pass when it has no cardinality moves (one Ceres problem for all its rounds); else
  /// final_solver_.
  std::optional<backend::StereoBatchMlSlam> batch_solver_;
  backend::StereoMlSlam::ControlList controls_;
  std::vector<backend::StereoMlSlam::MeasurementSet> scans_;
  PoseList filter_poses_;  ///< the filter's pose at each frame, as it was online
  PoseList refined_;
  std::size_t windows_ = 0;
  double window_ms_ = 0.0;
  int window_rounds_ = 0;
};

}  // namespace glmbslam::app
