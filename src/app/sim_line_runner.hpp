#pragma once
// `glmbslam sim --scenario paper004_1d --algorithm mlslam`: paper 004's 1D problem
// (src/sim/scenario_paper004_line.hpp) solved by RFS-ML-SLAM (backend/mlslam/line_ml_slam.hpp) from the
// odometry, or by the vector ML baseline with nearest-neighbour association (`mlslam.association:
// nearest_neighbour`), over Monte Carlo runs (run index = data seed). Writes DIR/metrics.json and, with
// plots, DIR/position_error.png (the mean absolute position error per step over the runs, the paper's Fig.
// 1–2 metric) and DIR/trajectory_map.png (run first_run).
#include <nlohmann/json.hpp>

#include "app/sim_runner.hpp"
#include "backend/mlslam/mlslam_config.hpp"

namespace glmbslam::app {

/// The solver's defaults on this scenario (a config file's `mlslam` mapping overrides them): one step at a
/// time, each new pose started by a 61-point search over ±3σ of the odometry noise (dead reckoning leaves the
/// known landmarks 10 σ_z away, outside every gate).
void set_paper004_line_defaults(backend::MlSlamConfig& c);

/// Runs the simulation (options already validated by run_simulation) and returns the metrics.
nlohmann::json run_line_simulation(const SimOptions& options, const backend::MlSlamConfig& config);

/// A one-line human summary of its metrics.
std::string summarize_line_simulation(const nlohmann::json& metrics);

}  // namespace glmbslam::app
