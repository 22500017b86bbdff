#include "app/pipeline/stereo_pipeline.hpp"

#include <string>

#include <spdlog/spdlog.h>

#include "core/progress.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::app {

StereoPipeline::StereoPipeline(const io::StereoDataset& dataset, const StereoCalibration& calibration,
                               const StereoConfig& config, std::size_t first, std::size_t last)
    : dataset_(dataset),
      config_(config),
      first_(first),
      last_(last),
      use_backend_(config.pipeline.algorithm != "vo"),
      frontend_(calibration, config.frontend),
      vo_(frontend_, config.frontend.vo, pixel_noise_options(config)) {
  vo_.set_first_frame(first);
  if (use_backend_) filter_.emplace(config, calibration);
}

void StereoPipeline::add_stage(std::unique_ptr<PipelineStage> stage) {
  stages_.push_back(std::move(stage));
}

void StereoPipeline::run(RunRecord& record, const std::function<bool()>& stop) {
  const std::size_t frames = last_ - first_;
  record.vo_poses.reserve(frames);
  FrameSource source(dataset_, frontend_, first_, last_, config_.pipeline.overlap_frontend);
  ProgressReporter progress(frames, "run");
  Stopwatch wall;
  std::size_t k = 0;
  for (; !source.done(); ++k) {
    if (stop && stop()) break;
    const FrameWork work = source.next();
    record.frontend_ms.push_back(work.frontend_ms);
    const frontend::VoEstimate& estimate = vo_.track(work, k);
    record.vo_ms.push_back(estimate.ms);
    record.vo_poses.push_back(vo_.pose());
    FrameOutcome outcome{k, work, estimate, vo_.pose()};
    if (filter_) {
      const FilterStep& step = filter_->step(work, estimate, vo_.odometry(), k);
      record.backend_ms.push_back(step.ms);
      const FilterStatus status = filter_->status();
      record.tracks.push_back(status.tracks);
      if (k > 0) {
        record.ess_fraction.push_back(status.ess / static_cast<double>(config_.rbpf.particles));
        record.resampled.push_back(status.resampled);
      }
      outcome.filter_step = &step;
      outcome.filter = &*filter_;
      progress.update(
          k + 1, "tracks " + std::to_string(status.tracks) + " hyp " + std::to_string(status.hypotheses));
    } else {
      progress.update(k + 1);
    }
    for (auto& stage : stages_) stage->on_frame(outcome);
  }
  frames_done_ = k;
  record.frames_requested = frames;
  record.interrupted = k < frames;  // the stages see it (the refinement skips its final pass)
  progress.finish_at(k, record.interrupted ? "stopped" : "");
  record.wall_s = wall.elapsed_ms() / 1000.0;
  record.vo_fallbacks = vo_.fallbacks();
  record.missing_frames = vo_.missing();
  if (vo_.repeated() > 0) {
    spdlog::info("{} frames repeated the previous stereo pair byte for byte (zero motion)", vo_.repeated());
  }
  if (vo_.fallbacks() + vo_.missing() > 0) {
    spdlog::info("VO fell back to constant velocity on {} frames ({} could not be loaded)",
                 vo_.fallbacks() + vo_.missing(), vo_.missing());
  }
  const frontend::PixelNoiseEstimator& noise = vo_.odometry().pixel_noise();
  if (noise.estimated()) {
    spdlog::info("keypoint noise estimated from the VO residuals: sigma {:.3f} px ({} samples){}",
                 noise.raw_sigma(), noise.samples(),
                 config_.pixel_sigma.automatic ? "" : ", not used (measurement.pixel_sigma is fixed)");
  }
  if (filter_) {
    record.slam_poses = filter_->trajectory();  // step 0 is the first frame (identity), then one per frame
    record.map = filter_->map_points();
  } else {
    record.slam_poses = record.vo_poses;
  }
  for (auto& stage : stages_) stage->on_finish(record);
}

}  // namespace glmbslam::app
