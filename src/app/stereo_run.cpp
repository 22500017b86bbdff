// `glmbslam run` on a stereo sequence (KITTI odometry or raw): reads the configuration, runs the stereo
// pipeline (pipeline/stereo_pipeline.hpp: reader + frontend → VO → δ-GLMB-SLAM 2.0 filter → later stages:
// the RFS-ML refinement with --refine ml) and writes trajectory.txt, vo_trajectory.txt, map.pcd,
// metrics.json, plots and the effective config (with --refine ml also trajectory_refined.txt and
// map_refined.pcd).
#include <sstream>

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include "app/pipeline/rectification_check_stage.hpp"
#include "app/pipeline/refinement_stage.hpp"
#include "app/pipeline/stereo_photometry_stage.hpp"
#include "app/pipeline/stereo_pipeline.hpp"
#include "app/pipeline/trajectory_stream_stage.hpp"
#include "app/run_options.hpp"
#include "app/run_outputs.hpp"
#include "app/stereo_config.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {
namespace {

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

}  // namespace

int run_stereo(const RunOptions& options) {
  if (!options.refine.empty() && options.refine != "ml")
    throw ConfigError("--refine must be ml, got '" + options.refine + "'");
  const auto dataset = io::open_stereo_dataset(options.dataset, options.format, options.ground_truth);
  YAML::Node root = load_config_document(options);
  if (options.particles) root["rbpf"]["particles"] = *options.particles;
  if (options.seed) root["rbpf"]["seed"] = *options.seed;
  if (options.algorithm) root["pipeline"]["algorithm"] = *options.algorithm;
  if (options.refine == "ml") root["refine"]["enabled"] = true;
  const std::string origin =
      options.config_file.empty() ? std::string("built-in defaults") : options.config_file;
  StereoConfig config = parse_stereo_config(root, origin);
  if (config.refine.enabled && config.pipeline.algorithm == "vo") {
    throw ConfigError(origin +
                      ": --refine ml (refine.enabled) refines a filter's estimate, and algorithm vo runs no "
                      "filter; choose another algorithm or leave the refinement off");
  }
  if (config.pipeline.max_measurements > 4096) {
    throw ConfigError(origin + ": key 'pipeline.max_measurements' must be at most 4096");
  }
  const std::string& algorithm = config.pipeline.algorithm;
  config.rbpf.proposal = algorithm == "glmb1" || algorithm == "lmb1" ? "prior" : "optimal";

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

  apply_camera_defaults(root, calibration, config);  // keys the config leaves out follow from the rig
  StereoPipeline pipeline(*dataset, calibration, config, first, last);
  pipeline.add_stage(std::make_unique<TrajectoryStreamStage>(options.out_dir));
  pipeline.add_stage(std::make_unique<RectificationCheckStage>());
  pipeline.add_stage(std::make_unique<StereoPhotometryStage>(config.frontend.stereo.gain_compensation));
  // SIGINT/SIGTERM: stop at the next frame boundary (or the final pass at its next EM round) and write what
  // we have
  const auto stop = [] { return interrupt_requested(); };
  if (config.refine.enabled) pipeline.add_stage(std::make_unique<RefinementStage>(config, calibration, stop));
  RunRecord record;
  set_graceful_interrupts(true);
  pipeline.run(record, stop);
  const std::size_t done = pipeline.frames_done();
  if (done < frames) spdlog::warn("interrupted after {} of {} frames; writing their outputs", done, frames);

  if (dataset->ground_truth() && done < 2) {
    spdlog::info("no evaluation: {} frame{} done, and the metrics compare motion between frames", done,
                 done == 1 ? "" : "s");
  }
  if (dataset->ground_truth() && done >= 2) {
    const PoseList& gt = *dataset->ground_truth();
    record.ground_truth = io::relative_to_first(
        PoseList(gt.begin() + static_cast<long>(first), gt.begin() + static_cast<long>(first + done)));
    const std::vector<char>& mask = dataset->ground_truth_mask();
    if (!mask.empty()) {
      record.ground_truth_mask.assign(mask.begin() + static_cast<long>(first),
                                      mask.begin() + static_cast<long>(first + done));
    }
  }
  record.dataset_name = dataset->name();
  record.algorithm = config.pipeline.algorithm;
  record.particles = config.rbpf.particles;
  record.seed = config.rbpf.seed;
  record.first_frame = first;
  std::ostringstream effective;
  effective << "# Effective configuration of this run (" << origin
            << ", with command-line overrides applied).\n# Keys absent here take their built-in defaults, "
               "documented in config/kitti00-02.yaml.\n"
            << YAML::Dump(root) << "\n";
  record.effective_config = effective.str();
  write_run_outputs(options.out_dir, record, config.pipeline.write_plots);
  remove_streamed_trajectories(options.out_dir);
  return 0;
}

}  // namespace glmbslam::app
