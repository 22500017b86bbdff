#pragma once
// The checks `glmbslam sim` makes on its options before any scenario is built, and the scenarios and
// algorithms it accepts: each listed once, for both the check and its error message.
#include <array>
#include <string_view>

#include "app/sim_runner.hpp"

namespace glmbslam::app {

/// --scenario's values (paper004_1d: app/sim_line_runner.hpp; the others: app/sim_scenarios.hpp).
inline constexpr std::array<std::string_view, 4> kSimScenarios = {"paper2019", "phdslam3", "paper004",
                                                                  "paper004_1d"};

/// --algorithm's values: the recursive filters, the baselines (app/baseline_filters.hpp), dead reckoning and
/// RFS-ML (app/sim_filter_run.hpp).
inline constexpr std::array<std::string_view, 11> kSimAlgorithms = {
    "glmb2", "glmb1",     "glmb_mh",         "phd1", "phd3",  "lmb",
    "lmb1",  "fastslam2", "fastslam2-known", "dr",   "mlslam"};

/// Throws ConfigError for a bad option; creates the output folder (ensure_writable_directory). Particles and
/// seed must already be resolved (with_filter_defaults, app/sim_filters.hpp).
void check_sim_options(const SimOptions& o);

}  // namespace glmbslam::app
