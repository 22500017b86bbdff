#pragma once
// Settings of RB-PHD-SLAM 1.0 (Mullane et al., paper 002; digest section 1) and PHD-SLAM 3.0 (proposal "mh"),
// defaults from paper 003 where 002 gives none (birth weight, pruning T = 1e-6, merging U = 50,
// gate 41.4465).
#include <cstdint>
#include <string>

#include "core/config_node.hpp"

namespace glmbslam::backend {

struct PhdConfig {
  int particles = 10;      ///< N
  std::uint64_t seed = 0;  ///< all randomness derives from (seed, step, particle)
  /// Particle likelihood g(Z_k | Z_{1:k−1}, X_{0:k}):
  ///  "empty_map"      Eq. 15 of 002 (the default of RB-PHD-SLAM 1.0): Πκ(z) · exp(N̂_k − N̂_{k|k−1} − λ_c);
  ///  "single_feature" the same identity evaluated at the strongest updated component (digest 1.3);
  ///  "poisson"        the exact Poisson-prior form of 003: −λ_c − ∫p_D v + Σ_z log(κ(z) + ∫Λ v).
  std::string likelihood = "empty_map";
  /// Pose proposal: "prior" (x ~ f(·|x⁻, u), RB-PHD-SLAM 1.0) or "mh" (paper 003's multi-hypothesis
  /// importance density on the GM-PHD map = PHD-SLAM 3.0; its settings, MhProposalConfig, are passed to the
  /// PhdSlam constructor — the top-level YAML section "mh" of `glmbslam run` / `glmbslam sim`)
  std::string proposal = "prior";
  std::string resampling = "always";  ///< "always" (every step) or "ess" (when ESS < ess_threshold · N)
  double ess_threshold = 0.5;
  double birth_weight = 1e-6;   ///< η_B of each birth component (003)
  bool birth_from_all = false;  ///< births from every measurement (002) instead of the unexplained ones (003)
  double prune_threshold = 1e-6;     ///< T: components with weight below are dropped (003)
  double merge_threshold = 50.0;     ///< U: Mahalanobis² merging radius (003)
  int max_components = 100000;       ///< J_max per particle (highest weights kept)
  double gate_threshold = 41.4465;   ///< χ² gate on νᵀS⁻¹ν (003: −2 ln 1e-9)
  double existence_threshold = 0.5;  ///< map estimate: components with weight above this (002)
  double fov_margin = 0.0;           ///< extra radius (m) beyond the sensor range for the active query
};

/// Keys = member names. Unknown keys are errors.
void load_phd_config(ConfigNode node, PhdConfig& config);

/// Throws ConfigError naming the first invalid setting.
void validate_phd_config(const PhdConfig& config);

}  // namespace glmbslam::backend
