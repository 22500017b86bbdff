#include "backend/phd/phd_config.hpp"

namespace glmbslam::backend {

void load_phd_config(ConfigNode node, PhdConfig& config) {
  node.read_in_range("particles", config.particles, 1, 1000000);
  int seed = static_cast<int>(config.seed);
  node.read_in_range("seed", seed, 0, 2147483647);
  config.seed = static_cast<std::uint64_t>(seed);
  node.read_choice("likelihood", config.likelihood, {"empty_map", "single_feature", "poisson"});
  node.read_choice("proposal", config.proposal, {"prior", "mh"});
  node.read_choice("resampling", config.resampling, {"always", "ess"});
  node.read_in_range("ess_threshold", config.ess_threshold, 0.0, 1.0);
  node.read_in_range("birth_weight", config.birth_weight, 0.0, 1.0);
  node.read("birth_from_all", config.birth_from_all);
  node.read_in_range("prune_threshold", config.prune_threshold, 0.0, 1.0);
  node.read_in_range("merge_threshold", config.merge_threshold, 0.0, 1e12);
  node.read_in_range("max_components", config.max_components, 1, 100000000);
  node.read_in_range("gate_threshold", config.gate_threshold, 0.0, 1e12);
  node.read_in_range("existence_threshold", config.existence_threshold, 0.0, 1e9);
  node.read_in_range("fov_margin", config.fov_margin, 0.0, 1e9);
  node.finish();
  validate_phd_config(config);
}

void validate_phd_config(const PhdConfig& c) {
  if (c.particles < 1) throw ConfigError("phd.particles must be at least 1");
  if (c.likelihood != "empty_map" && c.likelihood != "single_feature" && c.likelihood != "poisson") {
    throw ConfigError("phd.likelihood must be 'empty_map', 'single_feature' or 'poisson'");
  }
  if (c.proposal != "prior" && c.proposal != "mh") throw ConfigError("phd.proposal must be 'prior' or 'mh'");
  if (c.resampling != "always" && c.resampling != "ess") {
    throw ConfigError("phd.resampling must be 'always' or 'ess'");
  }
  if (!(c.birth_weight > 0.0)) throw ConfigError("phd.birth_weight must be positive");
  if (c.max_components < 1) throw ConfigError("phd.max_components must be at least 1");
}

}  // namespace glmbslam::backend
