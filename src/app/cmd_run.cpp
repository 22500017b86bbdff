// `glmbslam run DATASET`: SLAM on a dataset folder whose type is auto-detected (KITTI odometry sequence,
// KITTI raw drive, Victoria Park).
#include <spdlog/spdlog.h>

#include "app/commands.hpp"
#include "app/run_options.hpp"
#include "core/error.hpp"

namespace glmbslam::app {

void parse_frame_range(const std::string& text, std::size_t& first, std::size_t& last) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw ConfigError("--frames must be A:B (B exclusive), got '" + text + "'");
  auto parse = [&](const std::string& s, std::size_t fallback) -> std::size_t {
    if (s.empty()) return fallback;
    std::size_t used = 0;
    long long v = -1;
    try {
      v = std::stoll(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || v < 0)
      throw ConfigError("--frames must be A:B with non-negative integers, got '" + text + "'");
    return static_cast<std::size_t>(v);
  };
  first = parse(text.substr(0, colon), 0);
  last = parse(text.substr(colon + 1), 0);
  if (last != 0 && last <= first) throw ConfigError("--frames A:B needs B > A, got '" + text + "'");
}

void register_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  auto format = std::make_shared<std::string>("auto");
  auto frames = std::make_shared<std::string>();
  auto particles = std::make_shared<int>(0);
  auto seed = std::make_shared<long long>(-1);
  auto algorithm = std::make_shared<std::string>();
  auto* cmd =
      app.add_subcommand("run",
                         "Run SLAM on a dataset folder (KITTI odometry sequence, KITTI raw drive, EuRoC "
                         "MAV or Victoria Park), writing trajectory, map, metrics and plots");
  cmd->add_option(
         "dataset", options->dataset,
         "dataset folder: KITTI odometry sequences/XX, KITTI raw DATE/DATE_drive_NNNN_sync, an EuRoC MAV "
         "sequence (the folder holding mav0/), or the Victoria Park folder")
      ->required();
  cmd->add_option("--config", options->config_file,
                  "YAML config (default: built-in defaults; see config/*.yaml for every key)");
  cmd->add_option("--out", options->out_dir, "output folder")->capture_default_str();
  cmd->add_option("--format", *format, "dataset type: auto, kitti, kitti_raw, euroc or victoria_park")
      ->capture_default_str();
  cmd->add_option("--gt", options->ground_truth,
                  "ground-truth pose file (KITTI format) overriding the dataset's own");
  cmd->add_option("--frames", *frames, "frame range A:B (B exclusive; default: all frames)");
  CLI::Option* particles_option =
      cmd->add_option("--particles", *particles, "number of particles (overrides rbpf.particles)");
  CLI::Option* seed_option = cmd->add_option("--seed", *seed, "random seed ≥ 0 (overrides rbpf.seed)");
  cmd->add_option(
      "--refine", options->refine,
      "ml: refine the filter's trajectory and map by RFS maximum likelihood (paper 004): stereo and Victoria "
      "Park; the refined outputs (trajectory_refined.txt, map_refined.*, metrics.json `refined`) go beside "
      "the filter's");
  cmd->add_option("--algorithm", *algorithm,
                  "stereo: glmb2 (optimal kernel, default), glmb1 (prior proposal), lmb / lmb1 (LMB-SLAM, "
                  "optimal / prior proposal), vo (frontend only); "
                  "Victoria Park: see its config");
  cmd->callback([=] {
    RunOptions o = *options;
    o.format = io::parse_dataset_format(*format);
    if (!frames->empty()) parse_frame_range(*frames, o.first_frame, o.last_frame);
    if (particles_option->count() > 0) {
      if (*particles < 1)
        throw ConfigError("--particles must be at least 1, got " + std::to_string(*particles));
      o.particles = *particles;
    }
    if (seed_option->count() > 0) {
      if (*seed < 0) throw ConfigError("--seed must not be negative, got " + std::to_string(*seed));
      o.seed = static_cast<std::uint64_t>(*seed);
    }
    if (!algorithm->empty()) o.algorithm = *algorithm;
    const io::DatasetFormat detected =
        o.format == io::DatasetFormat::kAuto ? io::detect_dataset_format(o.dataset) : o.format;
    const int code = detected == io::DatasetFormat::kVictoriaPark ? run_victoria_park(o) : run_stereo(o);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace glmbslam::app
