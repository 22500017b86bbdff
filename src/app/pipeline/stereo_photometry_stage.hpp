#pragma once
// The right camera's contrast relative to the left's over a run (frontend.stereo.gain_compensation;
// frontend/stereo_gain.hpp), as metrics.json's `stereo_photometry` block, with a log line when the two
// cameras differ.
#include <map>
#include <string>
#include <vector>

#include "app/pipeline/pipeline_stage.hpp"

namespace glmbslam::app {

/// The contrast ratio from which a run says the cameras differ (a gain 5 % off 1).
inline constexpr double kStereoGainNoticeFraction = 0.05;

/// metrics.json's `stereo_photometry` block from the per-frame σ_L / σ_R (NaN entries: frames without an
/// estimate): frames (with an estimate), right_gain_median, right_gain_min, right_gain_max, compensated
/// (1/0). Logs the median when it is kStereoGainNoticeFraction or more off 1 (a warning when not
/// compensated).
std::map<std::string, double> stereo_photometry_metrics(const std::vector<double>& right_gains,
                                                        bool compensated);

class StereoPhotometryStage : public PipelineStage {
 public:
  explicit StereoPhotometryStage(bool compensated) : compensated_(compensated) {}
  void on_frame(const FrameOutcome& frame) override;
  void on_finish(RunRecord& record) override;

 private:
  bool compensated_;
  std::vector<double> gains_;
};

}  // namespace glmbslam::app
