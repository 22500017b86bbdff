#pragma once
// What an RFS maximum-likelihood SLAM solve reports (RfsMlSlam, StereoBatchMlSlam; paper 004's l of Eq. 8).
#include <vector>

namespace glmbslam::backend {

struct MlSlamReport {
  int rounds = 0;
  double initial_log_likelihood = 0.0;
  double final_log_likelihood = 0.0;
  std::vector<double> log_likelihood_per_round;  ///< l after each round (the objective being maximised)
  int births = 0, deaths = 0, merges = 0;        ///< accepted cardinality moves
  double ms = 0.0;
  double e_step_ms = 0.0, m_step_ms = 0.0;  ///< of ms: the E-steps (likelihood and β), the M-steps (Ceres)
  double moves_ms = 0.0;                    ///< of ms: the cardinality moves (candidates and their Δl)
  double motion_scale = 1.0;  ///< s of the motion noise s·Q at the end (1 unless motion_noise "estimated")
  bool stopped = false;       ///< the stop predicate ended the solve early (set_stop; an interrupted run)
};

}  // namespace glmbslam::backend
