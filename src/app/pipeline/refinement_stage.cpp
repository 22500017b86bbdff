#include "app/pipeline/refinement_stage.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>

#include <spdlog/spdlog.h>

#include "app/pipeline/landmark_frames.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::app {
namespace {

backend::MlSlamConfig with_rounds(backend::MlSlamConfig c, int rounds) {
  c.max_rounds = rounds;
  return c;
}

/// The landmarks of `map` that some pose of `poses` has in view, moved by `correction`.
backend::StereoMlSlam::LandmarkList landmarks_in_view(const std::vector<io::MapPoint>& map,
                                                      const Pose3& correction,
                                                      const backend::StereoMlSlam::PoseList& poses,
                                                      const backend::StereoMeasurementModel& model) {
  backend::StereoMlSlam::LandmarkList out;
  for (const auto& p : map) {
    const Eigen::Vector3d m = correction * p.position;
    for (const auto& x : poses) {
      if (!model.in_field_of_view(x, m)) continue;
      out.push_back(m);
      break;
    }
  }
  return out;
}

}  // namespace

RefinementStage::RefinementStage(const StereoConfig& config, const StereoCalibration& calibration,
                                 std::function<bool()> stop)
    : settings_(config.refine),
      motion_(config.motion),
      model_(calibration, config.measurement),
      automatic_pixel_sigma_(config.pixel_sigma.automatic),
      window_solver_(motion_, model_, with_rounds(config.refine.ml, config.refine.window_rounds)),
      final_solver_(motion_, model_, config.refine.final_pass_mlslam_config()) {
  if (config.refine.loop_closure && config.refine.final_pass)
    loop_closing_.emplace(config.refine.loop, calibration);
  if (backend::StereoBatchMlSlam::supports(config.refine.ml))
    batch_solver_.emplace(motion_, model_, config.refine.final_pass_mlslam_config());
  final_solver_.set_stop(stop);
  if (batch_solver_) batch_solver_->set_stop(std::move(stop));
}

void RefinementStage::on_frame(const FrameOutcome& frame) {
  if (frame.filter == nullptr || frame.filter_step == nullptr) return;  // no backend: nothing to refine
  const FilterStep& step = *frame.filter_step;
  // measurement.pixel_sigma auto: the filter's σ (the VO's estimate); the solvers' model copies share it
  if (automatic_pixel_sigma_) {
    model_.set_pixel_sigma(frame.vo.pixel_sigma);
    if (frame.vo.pixel_sigma_estimated) pixel_sigmas_.push_back(frame.vo.pixel_sigma);
  }
  scans_.emplace_back(step.Z.begin(), step.Z.end());
  if (loop_closing_ && frame.work.loaded) loop_closing_->add_frame(frame.k, frame.work.features.measurements);
  controls_.push_back(step.control);
  filter_poses_.push_back(frame.filter->pose());
  const std::size_t k = filter_poses_.size() - 1;
  // until a window refines it, a frame follows the filter's motion from the previous refined pose
  refined_.push_back(k == 0 ? filter_poses_[0]
                            : refined_[k - 1] * (filter_poses_[k - 1].inverse() * filter_poses_[k]));
  const auto W = static_cast<std::size_t>(settings_.window);
  if (W >= 2 && k + 1 >= 2 && (k + 1) % static_cast<std::size_t>(settings_.every) == 0)
    solve_window(k, frame.filter->map_points());
}

void RefinementStage::solve_window(std::size_t last, const std::vector<io::MapPoint>& filter_map) {
  Stopwatch watch;
  const std::size_t W = static_cast<std::size_t>(settings_.window);
  const std::size_t first = last + 1 >= W ? last + 1 - W : 0;
  backend::StereoMlSlam::PoseList poses(refined_.begin() + static_cast<long>(first),
                                        refined_.begin() + static_cast<long>(last + 1));
  const backend::StereoMlSlam::ControlList controls(controls_.begin() + static_cast<long>(first),
                                                    controls_.begin() + static_cast<long>(last + 1));
  const std::vector<backend::StereoMlSlam::MeasurementSet> scans(
      scans_.begin() + static_cast<long>(first), scans_.begin() + static_cast<long>(last + 1));
  // the filter's map in the refined frame: the correction at the held first pose
  const Pose3 correction = refined_[first] * filter_poses_[first].inverse();
  backend::StereoMlSlam::LandmarkList map = landmarks_in_view(filter_map, correction, poses, model_);
  const backend::MlSlamReport report = window_solver_.solve(poses, controls, scans, map);
  for (std::size_t i = 1; i < poses.size(); ++i) refined_[first + i] = poses[i];
  ++windows_;
  window_rounds_ += report.rounds;
  window_ms_ += watch.elapsed_ms();
}

void RefinementStage::on_finish(RunRecord& record) {
  if (refined_.empty()) return;
  std::map<std::string, double>& stats = record.refinement;
  stats["windows"] = static_cast<double>(windows_);
  stats["window_ms_mean"] = windows_ > 0 ? window_ms_ / static_cast<double>(windows_) : 0.0;
  stats["window_ms_total"] = window_ms_;
  stats["window_rounds_mean"] = windows_ > 0 ? window_rounds_ / static_cast<double>(windows_) : 0.0;
  record.refined_poses = refined_;
  // the filter's map moved into the refined frame by the correction at the last frame
  const Pose3 correction = refined_.back() * filter_poses_.back().inverse();
  record.refined_map = record.map;
  for (auto& p : record.refined_map) p.position = correction * p.position;
  // an interrupted run keeps the online result: the final pass is the long part
  if (!settings_.final_pass || record.interrupted || record.slam_poses.size() != refined_.size()) return;
  // auto: the run's σ, not its last stretch's (see the header; the last σ if none was estimated yet);
  // fixed: the configured σ
  if (!pixel_sigmas_.empty()) model_.set_pixel_sigma(quantile(pixel_sigmas_, 0.5));
  stats["final_pixel_sigma"] = std::sqrt(model_.noise()(0, 0));
  Stopwatch watch;
  const std::clock_t cpu_start = std::clock();  // the process's CPU time: the final pass on a loaded machine
  PoseList start = record.slam_poses;
  std::vector<io::MapPoint> start_map = record.map;
  if (settings_.final_start == "windows" && windows_ > 0) {
    // from the windows' trajectory, each landmark moved with the refinement of the frame that mapped it
    move_with_birth_frames(start_map, start, refined_);
    start = refined_;
  }
  if (loop_closing_) loop_closing_->apply(start, start_map, controls_, stats);
  backend::StereoMlSlam::PoseList poses(start.begin(), start.end());
  backend::StereoMlSlam::LandmarkList map;
  map.reserve(start_map.size());
  for (const auto& p : start_map) map.push_back(p.position);
  const backend::MlSlamReport r = batch_solver_ ? batch_solver_->solve(poses, controls_, scans_, map)
                                                : final_solver_.solve(poses, controls_, scans_, map);
  record.refined_poses = PoseList(poses.begin(), poses.end());
  record.refined_map.clear();
  for (std::size_t j = 0; j < map.size(); ++j)
    record.refined_map.push_back(io::MapPoint{map[j], static_cast<std::uint64_t>(j), 1.0});
  stats["final_ms"] = watch.elapsed_ms();
  stats["final_cpu_ms"] = 1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  stats["final_e_step_ms"] = r.e_step_ms;
  stats["final_m_step_ms"] = r.m_step_ms;
  stats["final_landmarks"] = static_cast<double>(map.size());
  stats["final_rounds"] = r.rounds;
  stats["final_log_likelihood_gain"] = r.final_log_likelihood - r.initial_log_likelihood;
  stats["final_births"] = r.births;
  stats["final_deaths"] = r.deaths;
  stats["final_merges"] = r.merges;
  if (r.stopped) {
    stats["final_interrupted"] = 1.0;
    record.interrupted = true;
    spdlog::warn("refinement: final pass interrupted after {} rounds; the refined outputs hold its estimate",
                 r.rounds);
  }
  for (std::size_t i = 0; i < r.log_likelihood_per_round.size(); ++i)
    spdlog::debug("refinement: final pass round {}: log-likelihood {:.3f}", i + 1,
                  r.log_likelihood_per_round[i]);
  spdlog::info(
      "refinement: {} windows ({:.1f} ms each), final pass {:.0f} ms, {} rounds, log-likelihood +{:.1f}",
      windows_, stats["window_ms_mean"], stats["final_ms"], r.rounds, stats["final_log_likelihood_gain"]);
}

}  // namespace glmbslam::app
