#pragma once
// Runs the row-alignment check of the stereo pair (frontend/rectification_check.hpp) on the frames of a run,
// puts its summary in metrics.json (`rectification`) and warns when the right image is off its rows by half a
// pixel or more at an image corner (two standard errors below the fitted value).
#include <map>
#include <string>

#include "app/pipeline/pipeline_stage.hpp"
#include "frontend/rectification_check.hpp"

namespace glmbslam::app {

/// The vertical offset at an image corner from which a run warns (pixels).
inline constexpr double kRectificationWarningPx = 0.5;

/// The check's summary as metrics.json's `rectification` block (samples, frames, median_vertical_offset_px
/// and, with enough samples, field_centre_px, field_x_px, field_y_px, field_xy_px, corner_max_px,
/// corner_max_se_px); logs the warning when corner_max_px − 2 corner_max_se_px reaches
/// kRectificationWarningPx.
std::map<std::string, double> rectification_metrics(const frontend::RectificationSummary& summary);

class RectificationCheckStage : public PipelineStage {
 public:
  void on_frame(const FrameOutcome& frame) override;
  void on_finish(RunRecord& record) override;

 private:
  frontend::RectificationCheck check_;
};

}  // namespace glmbslam::app
