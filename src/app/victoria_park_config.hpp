#pragma once
// Settings of the Victoria Park pipeline (config/victoria_park.yaml documents every key; the defaults here
// are the published protocol of paper 003 Sec. VI-B / ../shared/data/README.md).
#include <string>

#include <Eigen/Core>

#include "app/baseline_configs.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "backend/models/ackermann_motion.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/phd/phd_config.hpp"
#include "backend/rbpf/mh_proposal_config.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "io/victoria_park.hpp"

namespace glmbslam::app {

struct VictoriaParkConfig {
  /// glmb2 (optimal proposal), glmb1 (prior proposal), glmb-mh (multi-hypothesis proposal),
  /// phd1 (RB-PHD-SLAM 1.0, backend/phd), phd3 (PHD-SLAM 3.0: GM-PHD map + multi-hypothesis proposal),
  /// deadreckoning (noise-free motion model), lmb / lmb1 (LMB-SLAM with the optimal / prior proposal),
  /// fastslam2 (FastSLAM 2.0 with maximum-likelihood association)
  std::string algorithm = "glmb2";
  Eigen::Vector3d initial_pose{-67.6493, -41.7142, 35.5 * M_PI / 180.0};  ///< laser (x, y, φ) at t_0
  bool skip_empty_scans = true;  ///< scans without a real detection in view are not filter steps
  double clutter_rate = 5.0;     ///< artificial clutter λ per scan (generated; 0 = none)
  double gps_match_window_s = 0.025;
  io::GpsFilterOptions gps;
  backend::AckermannMotionConfig motion;
  backend::RangeBearingConfig measurement;
  backend::RbpfConfig rbpf;
  backend::MhProposalConfig mh;  ///< the multi-hypothesis proposal of glmb-mh and phd3
  backend::PhdConfig phd;        ///< phd1; particles and seed come from rbpf, proposal is 'prior'
  backend::PhdConfig phd3;       ///< phd3; particles and seed come from rbpf, proposal is 'mh'
  BaselineConfigs baselines;     ///< lmb, lmb1, fastslam2 (sections "lmb", "fastslam")
  backend::MlSlamConfig ml;      ///< mlslam and --refine ml (section "mlslam")
  bool write_plot = true;
  int threads = 1;  ///< worker threads (0 = all cores); 1 = the published single-core protocol
};

/// The particles the run's estimate carries: 1 for dead reckoning and the standalone RFS-ML solve (one
/// estimate each), rbpf.particles for the filters.
inline int victoria_park_particles(const VictoriaParkConfig& c) {
  return c.algorithm == "deadreckoning" || c.algorithm == "mlslam" ? 1 : c.rbpf.particles;
}

/// The protocol defaults (incl. the δ-GLMB/RBPF settings used for Victoria Park).
VictoriaParkConfig default_victoria_park_config();

/// Reads `path` over the defaults; unknown keys are ConfigErrors naming the key and file.
void load_victoria_park_config(const std::string& path, VictoriaParkConfig& config);
void load_victoria_park_config(ConfigNode node, VictoriaParkConfig& config);

}  // namespace glmbslam::app
