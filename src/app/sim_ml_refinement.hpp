#pragma once
// RFS maximum-likelihood SLAM (backend/mlslam) on a 2D simulation: standalone from odometry
// (`glmbslam sim --algorithm mlslam`) or as the refinement of a filter's estimate (`--refine ml`).
#include <vector>

#include <Eigen/Core>

#include "backend/mlslam/mlslam_config.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/steering_motion.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "sim/scenario2d.hpp"

namespace glmbslam::app {

struct MlSimResult {
  std::vector<Eigen::Vector3d> poses;  ///< one per step
  std::vector<Eigen::Vector2d> map;    ///< final landmark set
  double ms = 0.0;                     ///< wall time of the solve
  int rounds = 0;                      ///< EM rounds
  double log_likelihood = 0.0;         ///< l (Eq. 8) at the solution
  bool interrupted = false;            ///< SIGINT/SIGTERM stopped the solve (the run is left out)
};

/// Standalone: the trajectory from the odometry, the map from births (config.incremental_steps > 0: the
/// problem grows that many steps at a time).
template <class Motion>
MlSimResult run_mlslam(const Motion& motion, const backend::RangeBearingModel& model,
                       const sim::Scenario2D& scenario, const backend::MlSlamConfig& config);

/// Refinement of a filter's per-step pose estimates and final map.
template <class Motion>
MlSimResult refine_ml(const Motion& motion, const backend::RangeBearingModel& model,
                      const sim::Scenario2D& scenario, const backend::MlSlamConfig& config,
                      const std::vector<Eigen::Vector3d>& poses, const std::vector<Eigen::Vector2d>& map);

}  // namespace glmbslam::app
