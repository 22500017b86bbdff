#include "backend/lmb/lmb_config.hpp"

#include "core/error.hpp"

namespace glmbslam::backend {

void load_lmb_config(ConfigNode node, LmbConfig& config) {
  node.read_in_range("existence_threshold", config.existence_threshold, 0.0, 1.0);
  node.read_in_range("estimate_existence", config.estimate_existence, 0.0, 1.0);
  node.read_in_range("max_components", config.max_components, 1, 1000);
  node.read_in_range("component_prune", config.component_prune, 0.0, 1.0);
  node.finish();
  validate_lmb_config(config);
}

void validate_lmb_config(const LmbConfig& c) {
  if (!(c.existence_threshold >= 0.0 && c.existence_threshold < 1.0))
    throw ConfigError("lmb.existence_threshold must be in [0, 1)");
  if (!(c.estimate_existence >= 0.0 && c.estimate_existence <= 1.0))
    throw ConfigError("lmb.estimate_existence must be in [0, 1]");
  if (c.max_components < 1) throw ConfigError("lmb.max_components must be at least 1");
  if (!(c.component_prune >= 0.0 && c.component_prune < 1.0))
    throw ConfigError("lmb.component_prune must be in [0, 1)");
}

}  // namespace glmbslam::backend
