#include "app/baseline_configs.hpp"

namespace glmbslam::app {

bool is_baseline_algorithm(const std::string& a) {
  return a == "lmb" || a == "lmb1" || a == "fastslam2" || a == "fastslam2-known";
}

void load_baseline_configs(ConfigNode& root, BaselineConfigs& configs) {
  if (root.has("lmb")) backend::load_lmb_config(root.child("lmb"), configs.lmb);
  if (root.has("fastslam")) backend::load_fastslam_config(root.child("fastslam"), configs.fastslam);
}

void set_phdslam3_baseline_defaults(BaselineConfigs& configs) {
  configs.fastslam.resampling = "ess";
  configs.fastslam.ess_threshold = 0.2;
}

}  // namespace glmbslam::app
