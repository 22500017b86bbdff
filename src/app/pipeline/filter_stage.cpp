#include "app/pipeline/filter_stage.hpp"

#include <algorithm>

#include "core/stopwatch.hpp"

namespace glmbslam::app {

std::uint64_t pack_label(const backend::Label& l) {
  return (static_cast<std::uint64_t>(l.birth_step) << 12) | static_cast<std::uint64_t>(l.index & 0xFFF);
}

FilterStage::FilterStage(const StereoConfig& config, const StereoCalibration& calibration)
    : config_(config),
      motion_(config.motion),
      model_(calibration, config.measurement),
      filter_(motion_, model_, config.rbpf, Pose3::Identity()),
      rules_{config.measurement.min_depth, config.measurement.max_depth, config.pipeline.max_octave,
             config.pipeline.max_measurements},
      grid_{config.pipeline.grid_columns, config.pipeline.grid_rows, static_cast<double>(calibration.width),
            static_cast<double>(calibration.height)} {}

const FilterStep& FilterStage::step(const FrameWork& work, const frontend::VoEstimate& vo_estimate,
                                    const frontend::StereoVisualOdometry& vo, std::size_t k) {
  step_.Z.clear();
  step_.selected.clear();
  frontend::VoEstimate control = vo_estimate;
  if (work.loaded) {
    const auto& measurements = work.features.measurements;
    // prefer the features the VO tracked from last frame's selection (track continuity)
    std::vector<char> preferred;
    if (config_.pipeline.prefer_tracked && !vo_estimate.previous_measurement.empty()) {
      preferred.assign(measurements.size(), 0);
      for (std::size_t i = 0; i < preferred.size(); ++i) {
        const int prev = vo_estimate.previous_measurement[i];
        preferred[i] = prev >= 0 && static_cast<std::size_t>(prev) < previous_selected_.size() &&
                       previous_selected_[static_cast<std::size_t>(prev)];
      }
    }
    step_.selected = select_measurements(measurements, grid_, rules_, preferred);
    previous_selected_.assign(measurements.size(), 0);
    for (int i : step_.selected) previous_selected_[static_cast<std::size_t>(i)] = 1;
    if (config_.pipeline.control_excludes_selected) control = vo.excluding(vo_estimate, previous_selected_);
    step_.Z.reserve(step_.selected.size());
    for (int i : step_.selected) step_.Z.push_back(measurements[static_cast<std::size_t>(i)].z);
    if (model_.uses_appearance()) {  // index-aligned with Z; the filter's copies of the model share them
      std::vector<backend::StereoMeasurementModel::Appearance> descriptors;
      descriptors.reserve(step_.selected.size());
      for (int i : step_.selected)
        descriptors.push_back(measurements[static_cast<std::size_t>(i)].descriptor);
      model_.set_measurement_appearance(std::move(descriptors));
    }
  }
  step_.control.delta = control.relative_pose;
  step_.control.covariance = control.covariance;
  Stopwatch watch;
  if (k == 0) {
    filter_.initial_scan(step_.Z);  // the first frame's measurements anchor the map at the known initial pose
  } else {
    filter_.step(step_.control, step_.Z);
  }
  step_.ms = watch.elapsed_ms();
  return step_;
}

FilterStatus FilterStage::status() const {
  const auto& report = filter_.last_report();
  return FilterStatus{report.tracks, report.hypotheses, report.ess, report.resampled};
}

PoseList FilterStage::trajectory() const {
  const auto path = config_.pipeline.trajectory_estimate == "sample" ? filter_.trajectory()
                                                                     : filter_.estimated_trajectory();
  return PoseList(path.begin(), path.end());
}

std::vector<io::MapPoint> FilterStage::map_points() const {
  std::vector<io::MapPoint> points;
  for (const auto& lm : filter_.landmarks()) {
    points.push_back(io::MapPoint{lm.mean, pack_label(lm.label), std::clamp(lm.existence, 0.0, 1.0)});
  }
  return points;
}

}  // namespace glmbslam::app
