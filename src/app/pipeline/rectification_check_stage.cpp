#include "app/pipeline/rectification_check_stage.hpp"

#include <spdlog/spdlog.h>

namespace glmbslam::app {

std::map<std::string, double> rectification_metrics(const frontend::RectificationSummary& s) {
  std::map<std::string, double> m = {{"samples", static_cast<double>(s.samples)},
                                     {"frames", static_cast<double>(s.frames)},
                                     {"median_vertical_offset_px", s.median_px}};
  if (!s.valid()) return m;
  m["field_centre_px"] = s.field[0];
  m["field_x_px"] = s.field[1];
  m["field_y_px"] = s.field[2];
  m["field_xy_px"] = s.field[3];
  m["corner_max_px"] = s.corner_max_px;
  m["corner_max_se_px"] = s.corner_max_se_px;
  if (s.corner_max_px - 2.0 * s.corner_max_se_px >= kRectificationWarningPx) {
    spdlog::warn(
        "the stereo pair is not row-aligned: the right image is {:+.2f} px off the left's rows in the median "
        "and up to {:.2f} ± {:.2f} px at the image corners ({} matches re-aligned); stereo matching searches "
        "rows, so depths lose accuracy: check the calibration and rectification (metrics.json "
        "'rectification')",
        s.median_px, s.corner_max_px, s.corner_max_se_px, s.samples);
  }
  return m;
}

void RectificationCheckStage::on_frame(const FrameOutcome& frame) {
  if (frame.work.loaded) check_.add_frame(frame.k, frame.work.features);
}

void RectificationCheckStage::on_finish(RunRecord& record) {
  record.rectification = rectification_metrics(check_.summary());
}

}  // namespace glmbslam::app
