#include "app/pipeline/stereo_photometry_stage.hpp"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "core/stopwatch.hpp"

namespace glmbslam::app {

std::map<std::string, double> stereo_photometry_metrics(const std::vector<double>& right_gains,
                                                        bool compensated) {
  std::vector<double> g;
  g.reserve(right_gains.size());
  for (double x : right_gains)
    if (std::isfinite(x)) g.push_back(x);
  std::map<std::string, double> m = {{"frames", static_cast<double>(g.size())},
                                     {"compensated", compensated ? 1.0 : 0.0}};
  if (g.empty()) return m;
  const double median = quantile(g, 0.5);
  const auto [lo, hi] = std::minmax_element(g.begin(), g.end());
  m["right_gain_median"] = median;
  m["right_gain_min"] = *lo;
  m["right_gain_max"] = *hi;
  if (std::abs(median - 1.0) >= kStereoGainNoticeFraction) {
    if (compensated) {
      spdlog::info(
          "the left camera shows {:.2f}× the right's contrast in the median (frames {:.2f}…{:.2f}); levelled "
          "out before the sub-pixel stereo search (metrics.json 'stereo_photometry')",
          median, *lo, *hi);
    } else {
      spdlog::warn(
          "the left camera shows {:.2f}× the right's contrast in the median and frontend.stereo."
          "gain_compensation is off: the sub-pixel disparities are biased (metrics.json 'stereo_photometry')",
          median);
    }
  }
  return m;
}

void StereoPhotometryStage::on_frame(const FrameOutcome& frame) {
  if (frame.work.loaded) gains_.push_back(frame.work.features.stats.right_gain);
}

void StereoPhotometryStage::on_finish(RunRecord& record) {
  record.stereo_photometry = stereo_photometry_metrics(gains_, compensated_);
}

}  // namespace glmbslam::app
