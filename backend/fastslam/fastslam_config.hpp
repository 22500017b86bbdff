#pragma once
// Settings of FastSLAM 2.0 (Montemerlo et al. 2003; the known-association reference of paper 003).
#include <cstdint>
#include <string>

#include "core/config_node.hpp"

namespace glmbslam::backend {

struct FastSlamConfig {
  int particles = 10;      ///< N
  std::uint64_t seed = 0;  ///< all randomness derives from (seed, step, particle)
  /// Data association: "known" (every measurement carries the label of its true landmark, clutter −1: the
  /// oracle of paper 003; the caller passes the labels with set_measurement_labels) or "ml" (maximum
  /// likelihood per particle: greedy global nearest neighbour on the pose-marginal likelihood, a new landmark
  /// when no mapped landmark explains z better than new_landmark_likelihood)
  std::string association = "ml";
  /// p₀: measurement-space density [1/(unit of z)] below which a measurement starts a new landmark ("ml");
  /// each new landmark multiplies the particle weight by p₀, as in FastSLAM
  double new_landmark_likelihood = 1e-4;
  double gate_threshold = 13.8155;  ///< χ² gate on the pose-marginal innovation ("ml"; 2 dof: 1 − 1e-3)
  /// "ml": a landmark's score rises by 1 per detection and falls by p_D (at the sampled pose) per scan that
  /// misses it; below zero the landmark is removed (so landmarks started by clutter disappear)
  bool remove_unconfirmed = true;
  /// "ml" map estimate: landmarks detected at least this often (a clutter point starts a landmark that lives
  /// for a scan or two; "known" association never maps clutter, so its estimate is every landmark)
  int estimate_min_detections = 2;
  std::string resampling = "ess";  ///< "always" or "ess" (ESS below ess_threshold·N)
  double ess_threshold = 0.5;
  /// With one particle: "sample" draws the pose from the FastSLAM 2.0 proposal; "mean" takes its mean
  std::string single_particle = "sample";
};

/// Keys = member names. Unknown keys are errors.
void load_fastslam_config(ConfigNode node, FastSlamConfig& config);

/// Throws ConfigError naming the first invalid setting.
void validate_fastslam_config(const FastSlamConfig& config);

}  // namespace glmbslam::backend
