#pragma once
// Settings of the Rao–Blackwellised particle filter of δ-GLMB-SLAM (paper 000 Sec. 3; digest 0.4–0.5).
#include <cstdint>
#include <string>

#include "backend/glmb/glmb_config.hpp"
#include "core/config_node.hpp"

namespace glmbslam::backend {

struct RbpfConfig {
  int particles = 10;      ///< N_s
  std::uint64_t seed = 0;  ///< all randomness derives from (seed, step, particle)
  /// "prior" (δ-GLMB-SLAM 1.0), "optimal" (2.0, digest 0.5) or "mh" (paper 003's multi-hypothesis importance
  /// density, mh_proposal.hpp; its settings, MhProposalConfig, are passed to the GlmbSlam constructor — in
  /// the YAML files of `glmbslam run` (Victoria Park) and `glmbslam sim` they are the top-level section "mh")
  std::string proposal = "optimal";
  std::string weighting = "importance";  ///< "importance": w·Ĝ(x)·f(x|x⁻,u)/q(x); "paper": Eq. 33 as printed
  std::string resampling = "always";  ///< "always" (every step, paper 000) or "ess" (when ESS < threshold)
  double ess_threshold = 0.5;         ///< fraction of N_s below which "ess" resampling triggers
  // optimal-kernel proposal
  bool proposal_mixture = false;      ///< sample from the Gaussian mixture instead of its moment match
  int proposal_hypotheses = 3;        ///< map hypotheses used (the highest-weight ones) ...
  double proposal_min_weight = 1e-3;  ///< ... with at least this weight (the best one is always used)
  int proposal_gibbs_samples = 50;    ///< Gibbs sweeps per map hypothesis for the association hypotheses
  int proposal_max_components = 10;   ///< association hypotheses kept (highest weight first)
  /// Association rounds of the proposal: round 0 associates at the prediction (x̄, P̄); while the best
  /// hypothesis has a detection that fails the gate at the pose it implies, the next round re-associates at
  /// that pose (optimal_proposal.hpp). 1: round 0 only (paper 000)
  int proposal_association_rounds = 3;
  int ipl_iterations = 5;                ///< relinearisations of the FastSLAM-2.0 Gaussian (003 Algorithm 1)
  double ipl_tolerance = 1e-3;           ///< KL divergence at which the relinearisation stops
  double proposal_gate_threshold = 0.0;  ///< χ² gate with the pose-marginal S' (≤ 0: use glmb.gate_threshold)
  /// Birth candidates (GlmbMap::births: the previous scan's adaptive-birth Bernoullis) as extra rows of the
  /// proposal's association sampler, with the update's η of a birth: "never" (paper 000: tracks only),
  /// "empty_view" (only when no mapped landmark is in view of x̄, e.g. step 1 after initial_scan) or "always"
  std::string proposal_births = "never";
  /// Ĝ(x) in the particle weight: "sampled" (the sum over the Gibbs sampler's children, paper 000),
  /// "factorized" (GlmbUpdateStats::log_normalizer_factorized: no sampler noise, an upper bound where rows
  /// share a measurement) or "sibling_mean" (the sampled Ĝ averaged, log-mean-exp, over the children of one
  /// parent: they update the same map with the same measurements and, at proposal_scale 0, the same pose, so
  /// the exact G is theirs alike and their differences are the sampler's coverage alone)
  std::string particle_normalizer = "sampled";
  /// With one particle: "sample" draws the pose from the optimal-kernel proposal (paper 000); "mean" takes
  /// the proposal's mean (the minimum-MSE point; a lone particle has no weights to correct its draw noise)
  std::string single_particle = "sample";
  /// The particles draw their pose from the optimal-kernel proposal with every covariance scaled by this
  /// factor s, and weigh the draw by the density of that scaled proposal (the importance correction stays
  /// exact): 1 = paper 000; 0 < s < 1 narrower draws; 0 = no draw: the proposal mean (a mixture: the mean of
  /// a component drawn by weight), weighed by Ĝ(x) f(x|x⁻,u) / q(x), the Laplace approximation of the
  /// particle's marginal likelihood. Each draw's spread stays in the particle's map and every later pose (a
  /// resampled filter keeps one sampled history), so a draw as wide as the posterior adds error that the
  /// weights cannot remove. Range [0, 1]
  double proposal_scale = 1.0;
  GlmbConfig glmb;  ///< map update settings (YAML child "glmb")
};

/// Keys = member names; the map settings in the child mapping "glmb". Unknown keys are errors.
void load_rbpf_config(ConfigNode node, RbpfConfig& config);

}  // namespace glmbslam::backend
