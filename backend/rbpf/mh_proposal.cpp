#include "backend/rbpf/mh_proposal_config.hpp"

namespace glmbslam::backend {

void load_mh_proposal_config(ConfigNode node, MhProposalConfig& config) {
  node.read_in_range("max_assignments", config.max_assignments, 1, 100000);
  node.read_in_range("assignment_ratio", config.assignment_ratio, 1e-300, 1.0);
  node.read_in_range("ipl_iterations", config.ipl_iterations, 1, 100);
  node.read_in_range("ipl_tolerance", config.ipl_tolerance, 0.0, 1e6);
  node.read_in_range("gate_threshold", config.gate_threshold, 0.0, 1e6);
  node.read_in_range("fov_margin_sigmas", config.fov_margin_sigmas, 0.0, 100.0);
  node.read_choice("weights", config.weights, {"eq44", "prior_predictive"});
  node.read_choice("single_particle", config.single_particle, {"sample", "mean"});
  node.finish();
}

}  // namespace glmbslam::backend
