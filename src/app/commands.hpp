#pragma once
// Each subcommand of the glmbslam executable lives in its own cmd_<name>.cpp and registers itself here.
#include <CLI/CLI.hpp>

namespace glmbslam::app {

void register_run_command(CLI::App& app);  // cmd_run.cpp: SLAM on a dataset (KITTI, KITTI raw, Victoria Park)
void register_eval_command(CLI::App& app);    // cmd_eval.cpp: trajectory metrics against ground truth
void register_render_command(CLI::App& app);  // cmd_render.cpp: synthetic stereo KITTI-layout sequences
void register_vo_command(CLI::App& app);      // cmd_vo.cpp: stereo visual odometry only
void register_sim_command(CLI::App& app);     // cmd_sim.cpp: 2D Monte Carlo simulations of the papers

}  // namespace glmbslam::app
