#pragma once
// Stages that follow the filter in the stereo pipeline (refinement, streamed writers, …): each sees every
// frame once the filter has stepped on it, then the finished run.
#include <cstddef>

#include "app/pipeline/filter_stage.hpp"
#include "app/pipeline/frame_source.hpp"
#include "app/run_outputs.hpp"
#include "frontend/visual_odometry.hpp"

namespace glmbslam::app {

/// Everything the pipeline knows about frame k once the filter has stepped on it.
struct FrameOutcome {
  std::size_t k = 0;                        ///< position in the run, 0-based
  const FrameWork& work;                    ///< frontend output (index, features, load status)
  const frontend::VoEstimate& vo;           ///< VO motion from frame k−1 and its status
  const Pose3& vo_pose;                     ///< accumulated VO pose T_0k
  const FilterStep* filter_step = nullptr;  ///< Z, control and timing; null when the backend is off
  const FilterStage* filter = nullptr;      ///< the filter after its step k; null when the backend is off
};

class PipelineStage {
 public:
  virtual ~PipelineStage() = default;
  /// Called once per frame, in order, after the filter's step.
  virtual void on_frame(const FrameOutcome& frame) = 0;
  /// Called once after the last frame (or at an interruption), before the outputs are written; a stage may
  /// add its results to the record.
  virtual void on_finish(RunRecord& record) = 0;
};

}  // namespace glmbslam::app
