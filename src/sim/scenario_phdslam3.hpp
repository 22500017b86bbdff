#pragma once
// The synthetic benchmark of the multi-hypothesis importance density paper (PHD-SLAM 3.0, paper 003,
// digest 2.7): Gao et al.'s Environment_SLAM.mat (160 landmarks, 4000 steps, dt = 1 s), with measurements and
// odometry regenerated per Monte Carlo run as ../shared/data/README.md describes:
//  - the ground truth is the file's Robot_Groundtruth (x_k = f(x_{k−1}, Robot_Control_k), checked in the
//  tests);
//  - at each step k = 0..3999, every landmark with range ≤ 150 m and |bearing| ≤ 90° is measured; Poisson(5)
//    clutter points are drawn uniformly in range [0, 150] m × bearing [−90°, 90°]; every measurement
//    (landmark and clutter) gets R = diag(0.8², (0.3°)²) noise; each measurement is then kept with
//    probability 0.95 (the reference simulator thins the clutter too, so its effective rate is 4.75);
//  - odometry u_k = Robot_Control_k + N(0, Qodo) for k ≥ 1 (Qodo from the file: diag(0.8², (0.5°)²));
//  - seed = run index: RandomStream(run, 0) draws the odometry noise, RandomStream(run, 1) the measurements.
// The sensor parameters handed to the filters are the published ones: 150 m, ±90°, p_D 0.95, λ_c = 5.
#include <cstdint>
#include <filesystem>

#include "sim/scenario2d.hpp"

namespace glmbslam::sim {

/// The content of Environment_SLAM.mat.
struct PhdSlam3Environment {
  std::filesystem::path file;
  double dt = 1.0;
  std::vector<Eigen::Vector2d> landmarks;  ///< Landmark_Groundtruth(:, 2:3)
  std::vector<Eigen::Vector3d> poses;      ///< Robot_Groundtruth columns
  std::vector<Eigen::Vector2d> controls;   ///< Robot_Control columns (column k drives pose k−1 → k)
  Eigen::Matrix2d odometry_noise = Eigen::Matrix2d::Zero();  ///< Qodo
};

/// Reads and validates Environment_SLAM.mat: Landmark_Groundtruth n×5 (n ≥ 1), Robot_Groundtruth 3×K,
/// Robot_Control 2×K, Qodo 2×2 symmetric positive definite, T 1×1 > 0 (all real numeric, finite).
/// Throws InputError naming the file and the variable.
PhdSlam3Environment load_phdslam3_environment(const std::filesystem::path& mat_file);

struct PhdSlam3Options {
  double max_range = 150.0;       ///< [m]
  double max_bearing_deg = 90.0;  ///< [°]
  double detection_probability = 0.95;
  double clutter_rate = 5.0;       ///< λ_c per scan (before the 0.95 thinning)
  double sigma_range = 0.8;        ///< [m]
  double sigma_bearing_deg = 0.3;  ///< [°]
  std::size_t max_steps = 0;       ///< 0 = all steps; otherwise only the first max_steps (for quick tests)
};

/// One Monte Carlo realisation (seed = run index).
Scenario2D make_phdslam3_scenario(const PhdSlam3Environment& env, std::uint64_t run_index,
                                  const PhdSlam3Options& options = {});

/// Default location of the file below the shared data folder.
inline std::filesystem::path phdslam3_environment_path(const std::filesystem::path& data_root) {
  return data_root / "phdslam3_synthetic" / "Environment_SLAM.mat";
}

}  // namespace glmbslam::sim
