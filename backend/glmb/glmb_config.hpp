#pragma once
// Settings of the δ-GLMB map update (defaults from paper 000 where it gives them, digest 0.2–0.3).
#include "core/config_node.hpp"

namespace glmbslam::backend {

struct GlmbConfig {
  double birth_prob_unexplained = 1e-4;  ///< r_B for a measurement that gates with no mapped landmark (000)
  double birth_prob_explained = 5e-5;    ///< r_B for a measurement that gates with a mapped landmark (000)
  bool births = true;                    ///< adaptive birth from the previous scan
  double gate_threshold = 27.63;  ///< χ² gate on νᵀS⁻¹ν (27.63 = 1 − 1e-6 quantile for 2 dof)
  int gibbs_samples = 200;        ///< H_upd: Gibbs sweeps per update, shared by parents ∝ √ω
  int max_hypotheses = 100;       ///< H_max: hypotheses kept after pruning
  double prune_threshold = 1e-5;  ///< hypotheses with normalised weight below this are dropped (000)
  double fov_margin = 0.0;        ///< extra radius (m) beyond the sensor range for the active-track query
  /// Frozen tracks (frozen_tracks.hpp): tracks in every hypothesis farther than query radius + fov_margin +
  /// 2·freeze_margin leave the update until they come within query radius + fov_margin + freeze_margin.
  /// Must exceed the sensor's motion per step plus 3σ of the predicted position; ≤ 0 disables freezing.
  double freeze_margin = 0.0;
  int freeze_min_tracks = 64;  ///< freeze only when at least this many tracks qualify (keeps blocks large)
};

/// Keys = member names. Unknown keys are errors.
void load_glmb_config(ConfigNode node, GlmbConfig& config);

}  // namespace glmbslam::backend
