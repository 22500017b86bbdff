#include "app/pipeline/vo_stage.hpp"

#include <spdlog/spdlog.h>

namespace glmbslam::app {

VoStage::VoStage(const frontend::StereoFrontend& frontend, const frontend::VoConfig& config,
                 const frontend::PixelNoiseOptions& noise)
    : vo_(frontend.camera(), config, frontend.extractor().scales(), noise) {}

const frontend::VoEstimate& VoStage::track(const FrameWork& work, std::size_t k) {
  if (!work.loaded) {
    ++missing_;
    spdlog::warn("frame {}: {} — constant-velocity fallback, no measurements", work.index, work.load_error);
    estimate_ =
        k == 0 ? frontend::VoEstimate{} : vo_.skip_frame(frontend::VoStatus::kMissingImage, work.timestamp);
  } else {
    estimate_ = vo_.track(work.features, work.timestamp);
    if (estimate_.repeated()) ++repeated_;
    if (estimate_.fallback()) {
      ++fallbacks_;
      spdlog::debug("frame {}: VO fallback ({})", work.index, frontend::to_string(estimate_.status));
    }
  }
  if (k > 0) pose_ = pose_ * estimate_.relative_pose;
  return estimate_;
}

}  // namespace glmbslam::app
