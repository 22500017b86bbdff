#pragma once
// Systematic resampling.
#include <cstddef>
#include <vector>

#include "core/random.hpp"

namespace glmbslam::backend {

/// Systematic resampling of N normalised log weights: N indices, each i appearing ⌊N w_i⌋ or ⌈N w_i⌉ times
/// (so E[count_i] = N w_i). One uniform draw from `rng`.
std::vector<std::size_t> systematic_resample(const std::vector<double>& normalized_log_weights,
                                             RandomStream& rng);

}  // namespace glmbslam::backend
