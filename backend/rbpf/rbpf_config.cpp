#include "backend/rbpf/rbpf_config.hpp"

namespace glmbslam::backend {

void load_rbpf_config(ConfigNode node, RbpfConfig& config) {
  node.read_in_range("particles", config.particles, 1, 1000000);
  int seed = static_cast<int>(config.seed);
  node.read_in_range("seed", seed, 0, 2147483647);
  config.seed = static_cast<std::uint64_t>(seed);
  node.read_choice("proposal", config.proposal, {"prior", "optimal", "mh"});
  node.read_choice("weighting", config.weighting, {"importance", "paper"});
  node.read_choice("resampling", config.resampling, {"always", "ess"});
  node.read_in_range("ess_threshold", config.ess_threshold, 0.0, 1.0);
  node.read("proposal_mixture", config.proposal_mixture);
  node.read_in_range("proposal_hypotheses", config.proposal_hypotheses, 1, 100000);
  node.read_in_range("proposal_min_weight", config.proposal_min_weight, 0.0, 1.0);
  node.read_in_range("proposal_gibbs_samples", config.proposal_gibbs_samples, 1, 1000000);
  node.read_in_range("proposal_max_components", config.proposal_max_components, 1, 100000);
  node.read_in_range("proposal_association_rounds", config.proposal_association_rounds, 1, 100);
  node.read_in_range("ipl_iterations", config.ipl_iterations, 1, 100);
  node.read_in_range("ipl_tolerance", config.ipl_tolerance, 0.0, 1e6);
  node.read_in_range("proposal_gate_threshold", config.proposal_gate_threshold, 0.0, 1e6);
  node.read_choice("proposal_births", config.proposal_births, {"never", "empty_view", "always"});
  node.read_choice("particle_normalizer", config.particle_normalizer,
                   {"sampled", "factorized", "sibling_mean"});
  node.read_choice("single_particle", config.single_particle, {"sample", "mean"});
  node.read_in_range("proposal_scale", config.proposal_scale, 0.0, 1.0);
  load_glmb_config(node.child("glmb"), config.glmb);
  node.finish();
}

}  // namespace glmbslam::backend
