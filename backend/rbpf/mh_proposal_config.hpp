#pragma once
// Settings of the multi-hypothesis importance density (mh_proposal.hpp; paper 003 Sec. VI, digest 2.6).
#include <string>

#include "core/config_node.hpp"

namespace glmbslam::backend {

struct MhProposalConfig {
  int max_assignments = 50;         ///< Γ̄: Murty's ranked assignments at most
  double assignment_ratio = 1e-3;   ///< stop when an assignment is less likely than this × the best
  int ipl_iterations = 5;           ///< L: iterated posterior linearisation iterations
  double ipl_tolerance = 1e-3;      ///< ε: KL divergence between successive iterates that stops the IPL
  double gate_threshold = 41.4465;  ///< χ² gate on the pose-marginal innovation (1 − 1e-9 quantile, 2 dof)
  double fov_margin_sigmas = 3.0;   ///< margin (× position std of P̄) of the in-view landmark query
  /// Component weights: "eq44" (paper 003 Eq. 44: likelihoods at each component's posterior moments) or
  /// "prior_predictive" (the ranked assignment's own weight γ^t at x̄ with the pose-marginal innovation, i.e.
  /// Eq. 36–38 evaluated at the predicted pose; penalises assignments that need a large pose correction).
  std::string weights = "eq44";
  /// With a single particle (N = 1): "sample" draws the pose from the MH-ID (paper 003 Algorithm 2, step 9);
  /// "mean" takes the MH-ID's mixture mean instead. With N = 1 no weight can correct a draw, and the draw's
  /// noise (the proposal's covariance, every step) stays in the map, which is conditioned on the drawn
  /// trajectory: the single trajectory is a random walk around the filtered one. The mean is the point that
  /// minimises the expected squared error to a draw. No effect for N > 1 (the particles must be draws).
  std::string single_particle = "sample";
};

/// Loads the keys above (member names). Unknown keys are errors.
void load_mh_proposal_config(ConfigNode node, MhProposalConfig& config);

}  // namespace glmbslam::backend
