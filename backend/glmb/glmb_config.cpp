#include "backend/glmb/glmb_config.hpp"

namespace glmbslam::backend {

void load_glmb_config(ConfigNode node, GlmbConfig& config) {
  node.read_in_range("birth_prob_unexplained", config.birth_prob_unexplained, 0.0, 1.0);
  node.read_in_range("birth_prob_explained", config.birth_prob_explained, 0.0, 1.0);
  node.read("births", config.births);
  node.read_in_range("gate_threshold", config.gate_threshold, 0.0, 1e6);
  node.read_in_range("gibbs_samples", config.gibbs_samples, 1, 1000000);
  node.read_in_range("max_hypotheses", config.max_hypotheses, 1, 1000000);
  node.read_in_range("prune_threshold", config.prune_threshold, 0.0, 1.0);
  node.read_in_range("fov_margin", config.fov_margin, 0.0, 1e9);
  node.read_in_range("freeze_margin", config.freeze_margin, 0.0, 1e9);
  node.read_in_range("freeze_min_tracks", config.freeze_min_tracks, 1, 1000000000);
  node.finish();
}

}  // namespace glmbslam::backend
