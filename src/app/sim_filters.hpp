#pragma once
// The filter and solver settings of `glmbslam sim`: the built-in defaults (the phdslam3 benchmark's own),
// then a --config file's sections; and --particles / --seed, which fall back on them.
#include "app/baseline_configs.hpp"
#include "app/sim_runner.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "backend/phd/phd_config.hpp"
#include "backend/rbpf/mh_proposal_config.hpp"
#include "backend/rbpf/rbpf_config.hpp"

namespace glmbslam::app {

struct SimFilters {
  backend::RbpfConfig rbpf;
  backend::PhdConfig phd;        ///< phd1 (config key "phd")
  backend::PhdConfig phd3;       ///< phd3 = PHD-SLAM 3.0 (config key "phd3"; defaults: paper 003 Sec. VI)
  backend::MhProposalConfig mh;  ///< the multi-hypothesis proposal of glmb_mh and phd3 (config key "mh")
  backend::MlSlamConfig ml;      ///< mlslam and --refine ml (config key "mlslam")
  BaselineConfigs baselines;     ///< lmb, lmb1, fastslam2, fastslam2-known (config keys "lmb", "fastslam")
  SimFilters();
};

/// The settings for o.scenario, overridden by o.config_file's sections (ConfigError for unknown keys).
SimFilters load_sim_filters(const SimOptions& o);

/// `o` with unset --particles / --seed taken from the settings of o.algorithm (a flag overrides the config
/// file; without it the file's value, or the built-in default, holds).
SimOptions with_filter_defaults(SimOptions o, const SimFilters& f);

}  // namespace glmbslam::app
