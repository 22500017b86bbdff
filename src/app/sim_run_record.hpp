#pragma once
// What one Monte Carlo run of `glmbslam sim` produces (app/sim_filter_run.hpp), for the metrics
// (app/sim_metrics.hpp), the plots and report.html of its first run.
#include <vector>

#include <Eigen/Core>

#include "eval/ospa.hpp"

namespace glmbslam::app {

struct SimRunRecord {
  std::vector<Eigen::Vector3d> estimates;  // per step k = 0..K−1 (k = 0: the initial pose)
  std::vector<double> ospa;                // per step (paper2019), k = 1..K−1
  std::vector<double> gospa, cardinality;  // per step (paper2019): GOSPA (c, p of the OSPA, α = 2), |map|
  std::vector<Eigen::Vector2d> final_map;
  std::vector<double> ms, ess_fraction;
  int resampled = 0;
  eval::OspaResult final_ospa;
  eval::GospaResult final_gospa;
  int final_cardinality_error = 0;
  double filter_position_rmse = 0.0;  ///< --refine ml: the filter's, before the refinement
  double filter_gospa = 0.0;          ///< --refine ml: the filter's final-map GOSPA distance (phdslam3)
  std::vector<Eigen::Vector3d> filter_estimates;  ///< --refine ml: the filter's per-step estimates
  double ml_ms = 0.0;                             ///< --refine ml / mlslam: wall time of the ML solve
};

}  // namespace glmbslam::app
