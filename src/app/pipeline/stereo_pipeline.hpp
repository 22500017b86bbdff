#pragma once
// The stereo SLAM pipeline of `glmbslam run`, one frame at a time through its stages:
//   reader + frontend (FrameSource) → VO (VoStage) → filter (FilterStage) → later stages (PipelineStage:
//   refinement, streamed writers) → RunRecord for the writers (run_outputs.hpp).
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "app/pipeline/filter_stage.hpp"
#include "app/pipeline/frame_source.hpp"
#include "app/pipeline/pipeline_stage.hpp"
#include "app/pipeline/vo_stage.hpp"
#include "app/run_outputs.hpp"
#include "app/stereo_config.hpp"
#include "frontend/stereo_frontend.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::app {

class StereoPipeline {
 public:
  /// Frames [first, last) of `dataset`. The config must outlive the pipeline.
  StereoPipeline(const io::StereoDataset& dataset, const StereoCalibration& calibration,
                 const StereoConfig& config, std::size_t first, std::size_t last);

  /// Appends a stage that sees every frame after the filter.
  void add_stage(std::unique_ptr<PipelineStage> stage);

  /// Runs the frames in order until the last one or until `stop()` returns true at a frame boundary, then
  /// lets every stage finish. Fills the record's trajectories, map, timings and counters.
  void run(RunRecord& record, const std::function<bool()>& stop = {});

  /// Frames processed by the last run().
  std::size_t frames_done() const { return frames_done_; }

 private:
  const io::StereoDataset& dataset_;
  const StereoConfig& config_;
  std::size_t first_, last_;
  bool use_backend_;
  frontend::StereoFrontend frontend_;
  VoStage vo_;
  std::optional<FilterStage> filter_;
  std::vector<std::unique_ptr<PipelineStage>> stages_;
  std::size_t frames_done_ = 0;
};

}  // namespace glmbslam::app
