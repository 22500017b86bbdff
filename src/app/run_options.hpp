#pragma once
// Options of `glmbslam run`, shared by the pipelines it dispatches to (stereo KITTI, Victoria Park).
#include <cstdint>
#include <optional>
#include <string>

#include "io/stereo_dataset.hpp"

namespace glmbslam::app {

struct RunOptions {
  std::string dataset;                                  ///< dataset folder
  io::DatasetFormat format = io::DatasetFormat::kAuto;  ///< --format (auto-detected by default)
  std::string ground_truth;              ///< --gt: ground-truth pose file ("" = the dataset's own)
  std::string config_file;               ///< --config ("" = the default for the dataset)
  std::string out_dir = "out/run";       ///< --out
  std::optional<int> particles;          ///< --particles overrides the config
  std::optional<std::uint64_t> seed;     ///< --seed overrides the config
  std::optional<std::string> algorithm;  ///< --algorithm overrides the config (glmb2, glmb1, …)
  std::size_t first_frame = 0;           ///< --frames A:B (B exclusive; 0:0 = all)
  std::size_t last_frame = 0;
  std::string refine;  ///< --refine: "" or "ml" (RFS maximum-likelihood refinement, backend/mlslam)
};

/// Parses "A:B" (B exclusive, either side may be empty) into first/last; throws ConfigError otherwise.
void parse_frame_range(const std::string& text, std::size_t& first, std::size_t& last);

/// The Victoria Park pipeline (src/app/victoria_park_run.cpp). Returns the process exit code.
int run_victoria_park(const RunOptions& options);
/// The stereo pipeline for KITTI odometry / raw sequences (src/app/stereo_run.cpp). Returns the exit code.
int run_stereo(const RunOptions& options);

}  // namespace glmbslam::app
