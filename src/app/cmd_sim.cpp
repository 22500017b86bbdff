// `glmbslam sim`: Monte Carlo runs of the papers' simulations (paper2019, phdslam3, paper004, paper004_1d)
// with δ-GLMB-SLAM 2.0/1.0 (optimal/prior proposal) or with the multi-hypothesis proposal, RB-PHD-SLAM 1.0,
// PHD-SLAM 3.0 or dead reckoning; writes metrics.json and plots (app/sim_runner.hpp).
#include <iostream>

#include "app/commands.hpp"
#include "app/sim_runner.hpp"

namespace glmbslam::app {

void register_sim_command(CLI::App& app) {
  auto options = std::make_shared<SimOptions>();
  auto* cmd =
      app.add_subcommand("sim", "Monte Carlo runs of the papers' simulations (papers 000, 003 and 004)");
  cmd->add_option("--scenario", options->scenario,
                  "paper2019, phdslam3, paper004 (paper 004's small 2D problem) or paper004_1d (its 1D "
                  "problem; --algorithm mlslam only)")
      ->capture_default_str();
  cmd->add_option(
      "--refine", options->refine,
      "ml: refine the filter's estimate by RFS maximum likelihood (the run's figures are then the "
      "refined ones; metrics.json `ml` keeps the filter's)");
  cmd->add_option(
         "--algorithm", options->algorithm,
         "glmb2 (δ-GLMB-SLAM 2.0), glmb1 (1.0), glmb_mh (δ-GLMB map with the multi-hypothesis "
         "proposal of paper 003), phd1 (RB-PHD-SLAM 1.0), phd3 (PHD-SLAM 3.0: GM-PHD map with the "
         "multi-hypothesis proposal), lmb / lmb1 (LMB-SLAM with the optimal / prior proposal), fastslam2 "
         "(FastSLAM 2.0, maximum-likelihood association), fastslam2-known (FastSLAM 2.0 with the "
         "simulator's true landmark labels), dr (dead reckoning), mlslam (RFS maximum-likelihood SLAM of "
         "paper 004 from the odometry)")
      ->capture_default_str();
  cmd->add_option("--particles", options->particles,
                  "particles per filter (default: the config's rbpf.particles / phd.particles, else 10)");
  cmd->add_option("--runs", options->runs, "Monte Carlo runs (run in parallel)")->capture_default_str();
  cmd->add_option(
         "--first-run", options->first_run,
         "index of the first run (runs first-run .. first-run + runs - 1; phdslam3: the run index is "
         "the data realisation and the filter seed, so tuning runs can be kept apart from reported ones)")
      ->capture_default_str();
  cmd->add_option("--clutter", options->clutter,
                  "clutter rate λ_c per scan (paper2019: default 5; paper004 / paper004_1d: default the "
                  "paper's clutter intensity over the sensor's field of view)");
  cmd->add_option("--seed", options->seed,
                  "filter seed base, run r uses seed·1000003 + r (default: the config's rbpf.seed, else 0)");
  cmd->add_option("--config", options->config_file,
                  "YAML with optional 'rbpf', 'phd' (phd1, phd3), 'mh' (multi-hypothesis proposal), 'lmb', "
                  "'fastslam' and 'mlslam' mappings");
  cmd->add_option("--out", options->out_dir, "output folder (metrics.json, PNG plots)")->required();
  cmd->add_option("--data", options->data_dir, "shared data root (default $GLMBSLAM_DATA or ../shared/data)");
  cmd->add_option("--max-steps", options->max_steps, "only the first N steps (0 = all)")
      ->capture_default_str();
  cmd->add_flag("!--no-plots", options->plots, "do not write the PNG plots");
  cmd->callback([options] {
    const nlohmann::json metrics = run_simulation(*options);
    std::cout << summarize_simulation(metrics) << "\n";
  });
}

}  // namespace glmbslam::app
