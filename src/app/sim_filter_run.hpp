#pragma once
// One Monte Carlo run of `glmbslam sim`: --algorithm's filter (seeded with seed·1000003 + run) or RFS-ML over
// one scenario, then --refine ml, scored against the scenario's ground truth (app/sim_map_scoring.hpp).
#include "app/sim_filters.hpp"
#include "app/sim_run_record.hpp"
#include "app/sim_runner.hpp"
#include "sim/scenario2d.hpp"

namespace glmbslam::app {

/// Thrown by a run that stops at a step boundary on SIGINT/SIGTERM; the run is left out of the metrics.
struct SimRunInterrupted {};

/// Run `run` on `s` with the checked options `o` (particles and seed set).
SimRunRecord run_sim_filter(const sim::Scenario2D& s, const SimOptions& o, const SimFilters& f, int run);

}  // namespace glmbslam::app
