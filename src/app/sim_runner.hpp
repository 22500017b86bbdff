#pragma once
// The Monte Carlo driver behind `glmbslam sim`: builds a 2D scenario (src/sim), runs a backend filter on it R
// times in parallel (parallel over runs; each run's filter is seeded with (seed, run) and the phdslam3 data
// with seed = run index, so the result does not depend on the thread count), and writes metrics.json plus PNG
// plots.
//
// Algorithms: glmb2 = δ-GLMB-SLAM 2.0 (GlmbSlam, proposal "optimal"), glmb1 = δ-GLMB-SLAM 1.0 (proposal
// "prior"), phd1 = RB-PHD-SLAM 1.0 (PhdSlam, empty-map weight unless the config says otherwise). Scenarios:
// paper2019 (steering model, 360° 3 m sensor, λ_c from --clutter, default 5; one data realisation, the runs
// differ in the filter's randomness), phdslam3 (Environment_SLAM.mat, regenerated per run), paper004 (paper
// 004's 2D problem) and paper004_1d (its 1D problem, RFS-ML only: app/sim_line_runner.hpp).
//
// Stages: sim_filters.hpp (settings), sim_options_check.hpp, sim_scenarios.hpp, sim_monte_carlo.hpp (runs of
// sim_filter_run.hpp), sim_metrics.hpp, sim_outputs.hpp (plots, metrics.json, report.html).
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace glmbslam::app {

struct SimOptions {
  /// paper2019 | phdslam3 | paper004 | paper004_1d (app/sim_line_runner.hpp)
  std::string scenario = "paper2019";
  std::string algorithm = "glmb2";  ///< one of kSimAlgorithms (app/sim_options_check.hpp)
  std::string refine;               ///< "" or "ml": RFS-ML refinement of the filter's estimate
  /// Particles per filter; unset = the config file's rbpf.particles (phd.particles for phd1/phd3), or 10.
  std::optional<int> particles;
  int runs = 1;
  int first_run = 0;      ///< runs first_run .. first_run + runs − 1 (run index = data realisation, seed)
  double clutter = -1.0;  ///< λ_c per scan (paper2019, paper004, paper004_1d); < 0 = the scenario default
  /// Filter seed base (run r uses seed·1000003 + r); unset = the config file's rbpf.seed, or 0.
  std::optional<std::uint64_t> seed;
  std::string config_file;    ///< optional YAML: children "rbpf" (load_rbpf_config), "phd" (load_phd_config),
                              ///< "mlslam" (load_mlslam_config)
  std::string out_dir;        ///< metrics.json and plots
  std::string data_dir;       ///< shared data root (phdslam3); empty = $GLMBSLAM_DATA or ../shared/data
  std::size_t max_steps = 0;  ///< 0 = all steps (phdslam3: truncate for quick runs)
  bool plots = true;
};

/// Runs the Monte Carlo simulation and writes DIR/metrics.json (atomically) and the plots; returns the
/// metrics. Throws ConfigError for bad options, InputError for unreadable data. On SIGINT/SIGTERM
/// (core/interrupt.hpp) no further run starts and the runs in progress stop at their next step; the metrics
/// cover the runs that finished ("interrupted": true, "runs_requested", "run_indices").
nlohmann::json run_simulation(const SimOptions& options);

/// A one-line human summary of the metrics.
std::string summarize_simulation(const nlohmann::json& metrics);

}  // namespace glmbslam::app
