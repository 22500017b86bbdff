#pragma once
// Settings of the baseline filters of `glmbslam sim` and `glmbslam run` (baseline_filters.hpp): the YAML
// sections "lmb" (LmbConfig) and "fastslam" (FastSlamConfig).
#include <string>

#include "backend/fastslam/fastslam_config.hpp"
#include "backend/lmb/lmb_config.hpp"
#include "core/config_node.hpp"

namespace glmbslam::app {

struct BaselineConfigs {
  backend::LmbConfig lmb;
  backend::FastSlamConfig fastslam;
};

/// lmb, lmb1, fastslam2 or fastslam2-known.
bool is_baseline_algorithm(const std::string& algorithm);

/// Reads the optional children "lmb" and "fastslam" of `root` (unknown keys are errors).
void load_baseline_configs(ConfigNode& root, BaselineConfigs& configs);

/// The phdslam3 benchmark's settings (paper 003 Sec. VI: resampling when ESS < 0.2·N).
void set_phdslam3_baseline_defaults(BaselineConfigs& configs);

}  // namespace glmbslam::app
