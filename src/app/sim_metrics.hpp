#pragma once
// metrics.json of `glmbslam sim`: the finished runs' records aggregated into pose RMSE (overall, per step,
// per run), map OSPA / GOSPA (app/sim_map_scoring.hpp), cardinality error, timing, ESS and resampling.
#include <vector>

#include <nlohmann/json.hpp>

#include "app/sim_monte_carlo.hpp"
#include "app/sim_runner.hpp"
#include "sim/scenario2d.hpp"

namespace glmbslam::app {

/// The per-step curves over the runs that the plots draw: position (x, y) and heading RMSE for k = 0..K−1,
/// the mean map OSPA for k = 1..K−1 (paper2019; empty otherwise).
struct SimStepCurves {
  std::vector<double> rmse_x, rmse_y, rmse_h, ospa_mean;
};

struct SimMetrics {
  nlohmann::json json;  ///< metrics.json
  SimStepCurves curves;
};

/// metrics.json when no run finished (interrupted before the first).
nlohmann::json no_runs_metrics(const SimOptions& o, const SimRuns& runs);

/// The metrics of the finished runs (at least one) against `truth`, the scenario of the first (phdslam3
/// regenerates only the measurements and odometry per run: the poses are the same).
SimMetrics sim_metrics(const SimOptions& o, const SimRuns& runs, const sim::Scenario2D& truth,
                       double clutter_rate);

}  // namespace glmbslam::app
