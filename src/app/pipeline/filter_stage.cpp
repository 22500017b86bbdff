#include "app/pipeline/filter_stage.hpp"

#include <algorithm>
#include <memory>
#include <string>
#include <utility>

#include "backend/lmb/lmb_slam.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::app {

/// The stage's view of its particle filter: the calls the stage makes, whatever the algorithm.
class StereoBackend {
 public:
  virtual ~StereoBackend() = default;
  virtual void initial_scan(const StereoMeasurementSet& Z) = 0;
  virtual void step(const backend::RelativePoseControl& u, const StereoMeasurementSet& Z) = 0;
  /// A step whose camera saw nothing: the poses move with u, the maps stay.
  virtual void blind_step(const backend::RelativePoseControl& u) = 0;
  virtual Pose3 pose() const = 0;
  virtual FilterStatus status() const = 0;
  /// The best particle's sampled poses (`sampled`) or its proposal means, steps 0..k.
  virtual PoseList trajectory(bool sampled) const = 0;
  virtual std::vector<io::MapPoint> map_points() const = 0;
};

namespace {

using backend::Se3Motion;
using backend::StereoMeasurementModel;

/// δ-GLMB-SLAM (glmb2, glmb1) or LMB-SLAM (lmb, lmb1) behind StereoBackend.
template <class Filter>
class FilterBackend final : public StereoBackend {
 public:
  template <class... Args>
  explicit FilterBackend(Args&&... args) : filter_(std::forward<Args>(args)...) {}
  void initial_scan(const StereoMeasurementSet& Z) override { filter_.initial_scan(Z); }
  void step(const backend::RelativePoseControl& u, const StereoMeasurementSet& Z) override {
    filter_.step(u, Z);
  }
  void blind_step(const backend::RelativePoseControl& u) override { filter_.blind_step(u); }
  Pose3 pose() const override { return filter_.pose(); }
  FilterStatus status() const override {
    const auto& report = filter_.last_report();
    return FilterStatus{report.tracks, hypotheses(report), report.ess, report.resampled};
  }
  PoseList trajectory(bool sampled) const override {
    const auto path = sampled ? filter_.trajectory() : filter_.estimated_trajectory();
    return PoseList(path.begin(), path.end());
  }
  std::vector<io::MapPoint> map_points() const override {
    std::vector<io::MapPoint> points;
    for (const auto& lm : filter_.landmarks())
      points.push_back(io::MapPoint{lm.mean, pack_label(lm.label), std::clamp(lm.existence, 0.0, 1.0)});
    return points;
  }

 private:
  static int hypotheses(const backend::StepReport& report) { return report.hypotheses; }
  static int hypotheses(const backend::LmbStepReport&) { return 1; }  // one LMB per particle
  Filter filter_;
};

std::unique_ptr<StereoBackend> make_backend(const StereoConfig& config, const Se3Motion& motion,
                                            const StereoMeasurementModel& model) {
  const std::string& algorithm = config.pipeline.algorithm;
  if (algorithm == "lmb" || algorithm == "lmb1") {
    return std::make_unique<FilterBackend<backend::LmbSlam<Se3Motion, StereoMeasurementModel>>>(
        motion, model, config.rbpf, config.lmb, Pose3::Identity());
  }
  return std::make_unique<FilterBackend<backend::GlmbSlam<Se3Motion, StereoMeasurementModel>>>(
      motion, model, config.rbpf, Pose3::Identity());
}

}  // namespace

std::uint64_t pack_label(const backend::Label& l) {
  return (static_cast<std::uint64_t>(l.birth_step) << 12) | static_cast<std::uint64_t>(l.index & 0xFFF);
}

FilterStage::FilterStage(const StereoConfig& config, const StereoCalibration& calibration)
    : config_(config),
      motion_(config.motion),
      model_(calibration, config.measurement),
      filter_(make_backend(config, motion_, model_)),
      rules_{config.measurement.min_depth, config.measurement.max_depth, config.pipeline.max_octave,
             config.pipeline.max_measurements},
      grid_{config.pipeline.grid_columns, config.pipeline.grid_rows, static_cast<double>(calibration.width),
            static_cast<double>(calibration.height)} {}

FilterStage::~FilterStage() = default;

const FilterStep& FilterStage::step(const FrameWork& work, const frontend::VoEstimate& vo_estimate,
                                    const frontend::StereoVisualOdometry& vo, std::size_t k) {
  step_.Z.clear();
  step_.selected.clear();
  // a frame without images or without enough stereo measurements to track: the camera saw nothing (a
  // covered lens, a dark or blank frame), which says nothing about the landmarks in view
  step_.blind = k > 0 && (!work.loaded || vo_estimate.status == frontend::VoStatus::kNoFeatures);
  frontend::VoEstimate control = vo_estimate;
  if (work.loaded && !step_.blind) {
    const auto& measurements = work.features.measurements;
    // the features the VO tracked from last frame's selection: preferred (track continuity), and the ones
    // whose motion information reaches the backend through their landmarks
    const std::vector<char> tracked = tracked_from(vo_estimate.previous_measurement, previous_selected_);
    step_.selected = select_measurements(measurements, grid_, rules_,
                                         config_.pipeline.prefer_tracked ? tracked : std::vector<char>{});
    previous_selected_.assign(measurements.size(), 0);
    for (int i : step_.selected) previous_selected_[static_cast<std::size_t>(i)] = 1;
    if (config_.pipeline.control_excludes != "none")
      control = vo.excluding(
          vo_estimate, control_exclusion(config_.pipeline.control_excludes, previous_selected_, tracked));
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
  if (config_.pixel_sigma.automatic) model_.set_pixel_sigma(vo_estimate.pixel_sigma);  // the sequence's σ
  step_.control.delta = control.relative_pose;
  step_.control.covariance = control.covariance;
  Stopwatch watch;
  if (k == 0) {
    filter_->initial_scan(
        step_.Z);  // the first frame's measurements anchor the map at the known initial pose
  } else if (step_.blind) {
    filter_->blind_step(step_.control);
  } else {
    filter_->step(step_.control, step_.Z);
  }
  step_.ms = watch.elapsed_ms();
  return step_;
}

Pose3 FilterStage::pose() const {
  return filter_->pose();
}

FilterStatus FilterStage::status() const {
  return filter_->status();
}

PoseList FilterStage::trajectory() const {
  return filter_->trajectory(config_.pipeline.trajectory_estimate == "sample");
}

std::vector<io::MapPoint> FilterStage::map_points() const {
  return filter_->map_points();
}

}  // namespace glmbslam::app
