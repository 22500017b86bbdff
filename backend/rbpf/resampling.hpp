#pragma once
// Systematic resampling.
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/random.hpp"

namespace glmbslam::backend {

/// Systematic resampling of N normalised log weights: N indices, each i appearing ⌊N w_i⌋ or ⌈N w_i⌉ times
/// (so E[count_i] = N w_i). One uniform draw from `rng`.
std::vector<std::size_t> systematic_resample(const std::vector<double>& normalized_log_weights,
                                             RandomStream& rng);

/// Replaces `particles` by a systematic resample of themselves (weights set to 1/N). `scratch` is reusable
/// storage of the caller; particles hold shared pointers, so this copies pointers, not maps. Used by every
/// particle filter of the backend (δ-GLMB-SLAM, PHD-SLAM, the multi-hypothesis filter).
template <class Particle>
void resample_particles(std::vector<Particle>& particles, std::vector<Particle>& scratch,
                        const std::vector<double>& normalized_log_weights, RandomStream& rng) {
  const std::vector<std::size_t> idx = systematic_resample(normalized_log_weights, rng);
  const double log_uniform = -std::log(static_cast<double>(particles.size()));
  scratch.resize(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    scratch[i] = particles[idx[i]];
    scratch[i].log_weight = log_uniform;
  }
  particles.swap(scratch);
  for (auto& p : scratch) p = Particle{};  // release the references held by the old copies
}

}  // namespace glmbslam::backend
