#include "backend/fastslam/fastslam_config.hpp"

#include "core/error.hpp"

namespace glmbslam::backend {

void load_fastslam_config(ConfigNode node, FastSlamConfig& config) {
  node.read_in_range("particles", config.particles, 1, 1000000);
  int seed = static_cast<int>(config.seed);
  node.read_in_range("seed", seed, 0, 2147483647);
  config.seed = static_cast<std::uint64_t>(seed);
  node.read_choice("association", config.association, {"known", "ml"});
  node.read_in_range("new_landmark_likelihood", config.new_landmark_likelihood, 1e-300, 1e300);
  node.read_in_range("gate_threshold", config.gate_threshold, 0.0, 1e12);
  node.read("remove_unconfirmed", config.remove_unconfirmed);
  node.read_in_range("estimate_min_detections", config.estimate_min_detections, 1, 1000000);
  node.read_choice("resampling", config.resampling, {"always", "ess"});
  node.read_in_range("ess_threshold", config.ess_threshold, 0.0, 1.0);
  node.read_choice("single_particle", config.single_particle, {"sample", "mean"});
  node.finish();
  validate_fastslam_config(config);
}

void validate_fastslam_config(const FastSlamConfig& c) {
  if (c.particles < 1) throw ConfigError("fastslam.particles must be at least 1");
  if (c.association != "known" && c.association != "ml")
    throw ConfigError("fastslam.association must be 'known' or 'ml'");
  if (!(c.new_landmark_likelihood > 0.0))
    throw ConfigError("fastslam.new_landmark_likelihood must be positive");
  if (c.resampling != "always" && c.resampling != "ess")
    throw ConfigError("fastslam.resampling must be 'always' or 'ess'");
  if (c.single_particle != "sample" && c.single_particle != "mean")
    throw ConfigError("fastslam.single_particle must be 'sample' or 'mean'");
  if (c.estimate_min_detections < 1) throw ConfigError("fastslam.estimate_min_detections must be at least 1");
}

}  // namespace glmbslam::backend
