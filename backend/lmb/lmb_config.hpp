#pragma once
// Settings of the LMB-SLAM map (the labelled multi-Bernoulli approximation after each δ-GLMB update; the
// update itself uses the δ-GLMB settings of RbpfConfig::glmb: gate, Gibbs sweeps, adaptive birth).
#include "core/config_node.hpp"

namespace glmbslam::backend {

struct LmbConfig {
  /// Bernoullis whose posterior existence falls below are removed (paper 000: 0.019, which prunes the
  /// features created by clutter)
  double existence_threshold = 0.019;
  double estimate_existence = 0.5;  ///< map estimate: Bernoullis with existence above this
  /// Gaussian components kept per label: the highest-weight max_components − 1 as they are, the rest merged
  /// by moment matching into one (1 = every label's density moment-matched to one Gaussian)
  int max_components = 1;
  double component_prune = 1e-4;  ///< components of a label with relative weight below this are dropped
};

/// Keys = member names. Unknown keys are errors.
void load_lmb_config(ConfigNode node, LmbConfig& config);

/// Throws ConfigError naming the first invalid setting.
void validate_lmb_config(const LmbConfig& config);

}  // namespace glmbslam::backend
