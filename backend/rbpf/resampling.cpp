#include "backend/rbpf/resampling.hpp"

#include <cmath>

namespace glmbslam::backend {

std::vector<std::size_t> systematic_resample(const std::vector<double>& normalized_log_weights,
                                             RandomStream& rng) {
  const std::size_t n = normalized_log_weights.size();
  std::vector<std::size_t> out;
  out.reserve(n);
  if (n == 0) return out;
  const double u0 = rng.uniform() / static_cast<double>(n);
  double cumulative = std::exp(normalized_log_weights[0]);
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double u = u0 + static_cast<double>(k) / static_cast<double>(n);
    while (u > cumulative && i + 1 < n) cumulative += std::exp(normalized_log_weights[++i]);
    out.push_back(i);
  }
  return out;
}

}  // namespace glmbslam::backend
