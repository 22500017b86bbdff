// `glmbslam run` on a stereo sequence (KITTI odometry or raw): frontend → VO → δ-GLMB-SLAM 2.0 backend →
// trajectory.txt, vo_trajectory.txt, map.pcd, metrics.json, plots and the effective config.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <future>
#include <sstream>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "app/measurement_selection.hpp"
#include "app/run_options.hpp"
#include "app/run_outputs.hpp"
#include "app/stereo_config.hpp"
#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/stopwatch.hpp"
#include "frontend/stereo_frontend.hpp"
#include "frontend/visual_odometry.hpp"
#include "io/pcd_writer.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {
namespace {

using Filter = backend::GlmbSlam<backend::Se3Motion, backend::StereoMeasurementModel>;

/// Features of one frame computed (possibly on another thread) ahead of the backend.
struct FrameWork {
  bool loaded = false;
  std::string load_error;
  frontend::StereoFrameFeatures features;
  double frontend_ms = 0.0;
};

FrameWork process_frame(const io::StereoDataset& dataset, const frontend::StereoFrontend& fe,
                        std::size_t index) {
  FrameWork w;
  Stopwatch watch;
  try {
    const io::StereoFrame frame = dataset.load(index);
    w.features = fe.process(frame.left, frame.right);
    w.loaded = true;
  } catch (const InputError& e) {
    w.load_error = e.what();
  }
  w.frontend_ms = watch.elapsed_ms();
  return w;
}

YAML::Node load_config_document(const RunOptions& options) {
  if (options.config_file.empty()) return YAML::Node(YAML::NodeType::Map);
  try {
    YAML::Node root = YAML::LoadFile(options.config_file);
    return root.IsNull() ? YAML::Node(YAML::NodeType::Map) : root;
  } catch (const YAML::BadFile&) {
    throw InputError(options.config_file, "config file not found or unreadable");
  } catch (const YAML::Exception& e) {
    throw InputError(options.config_file, std::string("invalid YAML: ") + e.what());
  }
}

/// Labels (birth step, index) packed into 32 bits for the PCD map.
std::uint64_t pack_label(const backend::Label& l) {
  return (static_cast<std::uint64_t>(l.birth_step) << 12) | static_cast<std::uint64_t>(l.index & 0xFFF);
}

}  // namespace

int run_stereo(const RunOptions& options) {
  const auto dataset = io::open_stereo_dataset(options.dataset, options.format, options.ground_truth);
  YAML::Node root = load_config_document(options);
  if (options.particles) root["rbpf"]["particles"] = *options.particles;
  if (options.seed) root["rbpf"]["seed"] = *options.seed;
  if (options.algorithm) root["pipeline"]["algorithm"] = *options.algorithm;
  const std::string origin =
      options.config_file.empty() ? std::string("built-in defaults") : options.config_file;
  StereoConfig config = parse_stereo_config(root, origin);
  if (config.pipeline.max_measurements > 4096) {
    throw ConfigError(origin + ": key 'pipeline.max_measurements' must be at most 4096");
  }
  config.rbpf.proposal = config.pipeline.algorithm == "glmb1" ? "prior" : "optimal";
  const bool use_backend = config.pipeline.algorithm != "vo";

  const std::size_t first = options.first_frame;
  const std::size_t last = options.last_frame == 0 ? dataset->size() : options.last_frame;
  if (first >= last || last > dataset->size()) {
    throw InputError(options.dataset, "frame range " + std::to_string(first) + ":" + std::to_string(last) +
                                          " is outside the sequence of " + std::to_string(dataset->size()) +
                                          " frames");
  }
  const std::size_t frames = last - first;
  ensure_writable_directory(options.out_dir);

  StereoCalibration calibration = dataset->calibration();
  if (calibration.width <= 0 || calibration.height <= 0) {
    const io::StereoFrame probe = dataset->load(first);
    calibration.width = probe.left.cols;
    calibration.height = probe.left.rows;
  }
  spdlog::info("{}: frames {}..{} ({} frames), {}x{}, algorithm {}, {} particles, seed {}", dataset->name(),
               first, last - 1, frames, calibration.width, calibration.height, config.pipeline.algorithm,
               config.rbpf.particles, config.rbpf.seed);

  const frontend::StereoFrontend fe(calibration, config.frontend);
  frontend::StereoVisualOdometry vo(fe.camera(), config.frontend.vo, fe.extractor().scales());
  const backend::Se3Motion motion(config.motion);
  const backend::StereoMeasurementModel model(calibration, config.measurement);
  Filter filter(motion, model, config.rbpf, Pose3::Identity());
  const SelectionRules selection_rules{config.measurement.min_depth, config.measurement.max_depth,
                                       config.pipeline.max_octave, config.pipeline.max_measurements};
  const SelectionGrid grid{config.pipeline.grid_columns, config.pipeline.grid_rows,
                           static_cast<double>(calibration.width), static_cast<double>(calibration.height)};

  RunRecord record;
  record.vo_poses.reserve(frames);
  Pose3 vo_pose = Pose3::Identity();
  ProgressReporter progress(frames, "run");
  Stopwatch wall;
  std::future<FrameWork> ahead;
  std::size_t fallbacks = 0, missing = 0;
  std::vector<char> previous_selected;  // per measurement of the previous frame: handed to the backend
  for (std::size_t k = 0; k < frames; ++k) {
    const std::size_t index = first + k;
    FrameWork work = ahead.valid() ? ahead.get() : process_frame(*dataset, fe, index);
    if (k + 1 < frames && config.pipeline.overlap_frontend) {
      ahead = std::async(std::launch::async, process_frame, std::cref(*dataset), std::cref(fe), index + 1);
    }
    record.frontend_ms.push_back(work.frontend_ms);
    frontend::VoEstimate est;
    if (!work.loaded) {
      ++missing;
      spdlog::warn("frame {}: {} — constant-velocity fallback, no measurements", index, work.load_error);
      est = k == 0 ? frontend::VoEstimate{} : vo.skip_frame(frontend::VoStatus::kMissingImage);
    } else {
      est = vo.track(work.features);
      if (est.fallback()) {
        ++fallbacks;
        spdlog::debug("frame {}: VO fallback ({})", index, frontend::to_string(est.status));
      }
    }
    record.vo_ms.push_back(est.ms);
    if (k > 0) vo_pose = vo_pose * est.relative_pose;
    record.vo_poses.push_back(vo_pose);

    if (use_backend) {
      frontend::VoEstimate control = est;  // u_k, Q_k for the backend
      Filter::MeasurementSet Z;
      if (work.loaded) {
        // prefer the features the VO tracked from last frame's selection (track continuity)
        std::vector<char> preferred;
        if (config.pipeline.prefer_tracked && !est.previous_measurement.empty()) {
          preferred.assign(work.features.measurements.size(), 0);
          for (std::size_t i = 0; i < preferred.size(); ++i) {
            const int prev = est.previous_measurement[i];
            preferred[i] = prev >= 0 && static_cast<std::size_t>(prev) < previous_selected.size() &&
                           previous_selected[static_cast<std::size_t>(prev)];
          }
        }
        const auto chosen = select_measurements(work.features.measurements, grid, selection_rules, preferred);
        previous_selected.assign(work.features.measurements.size(), 0);
        for (int i : chosen) previous_selected[static_cast<std::size_t>(i)] = 1;
        if (config.pipeline.control_excludes_selected) control = vo.excluding(est, previous_selected);
        Z.reserve(chosen.size());
        for (int i : chosen) Z.push_back(work.features.measurements[static_cast<std::size_t>(i)].z);
        if (model.uses_appearance()) {  // index-aligned with Z; the filter's copies of the model share them
          std::vector<backend::StereoMeasurementModel::Appearance> descriptors;
          descriptors.reserve(chosen.size());
          for (int i : chosen)
            descriptors.push_back(work.features.measurements[static_cast<std::size_t>(i)].descriptor);
          model.set_measurement_appearance(std::move(descriptors));
        }
      }
      Stopwatch backend_watch;
      if (k == 0) {
        filter.initial_scan(Z);  // the first frame's measurements anchor the map at the known initial pose
      } else {
        backend::RelativePoseControl u;
        u.delta = control.relative_pose;
        u.covariance = control.covariance;
        filter.step(u, Z);
      }
      record.backend_ms.push_back(backend_watch.elapsed_ms());
      const auto& rep = filter.last_report();
      if (k > 0) {
        record.ess_fraction.push_back(rep.ess / static_cast<double>(config.rbpf.particles));
        record.resampled.push_back(rep.resampled);
      }
      progress.update(k + 1,
                      "tracks " + std::to_string(rep.tracks) + " hyp " + std::to_string(rep.hypotheses));
    } else {
      progress.update(k + 1);
    }
  }
  progress.finish();
  record.wall_s = wall.elapsed_ms() / 1000.0;
  if (fallbacks + missing > 0) {
    spdlog::info("VO fell back to constant velocity on {} frames ({} could not be loaded)",
                 fallbacks + missing, missing);
  }

  // Outputs.
  if (use_backend) {
    // step 0 is the first frame (identity), then one step per frame
    const auto path =
        config.pipeline.trajectory_estimate == "sample" ? filter.trajectory() : filter.estimated_trajectory();
    record.slam_poses.assign(path.begin(), path.end());
    for (const auto& lm : filter.landmarks()) {
      record.map.push_back(io::MapPoint{lm.mean, pack_label(lm.label), std::clamp(lm.existence, 0.0, 1.0)});
    }
  } else {
    record.slam_poses = record.vo_poses;
  }
  if (dataset->ground_truth()) {
    const PoseList& gt = *dataset->ground_truth();
    record.ground_truth = io::relative_to_first(
        PoseList(gt.begin() + static_cast<long>(first), gt.begin() + static_cast<long>(last)));
  }
  record.dataset_name = dataset->name();
  record.algorithm = config.pipeline.algorithm;
  record.particles = config.rbpf.particles;
  record.seed = config.rbpf.seed;
  record.first_frame = first;
  record.vo_fallbacks = fallbacks;
  record.missing_frames = missing;
  std::ostringstream effective;
  effective << "# Effective configuration of this run (" << origin
            << ", with command-line overrides applied).\n# Keys absent here take their built-in defaults, "
               "documented in config/kitti00-02.yaml.\n"
            << YAML::Dump(root) << "\n";
  record.effective_config = effective.str();
  write_run_outputs(options.out_dir, record, config.pipeline.write_plots);
  return 0;
}

}  // namespace glmbslam::app
