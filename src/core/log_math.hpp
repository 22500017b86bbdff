#pragma once
// Log-space arithmetic: probabilities and weights are kept as logarithms throughout the project.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace glmbslam {

inline constexpr double kLogZero = -std::numeric_limits<double>::infinity();

/// log(e^a + e^b) without overflow; either argument may be −∞.
inline double log_add(double a, double b) {
  if (a == kLogZero) return b;
  if (b == kLogZero) return a;
  const double m = std::max(a, b);
  return m + std::log1p(std::exp(-std::abs(a - b)));
}

/// log Σ e^{x_i}; −∞ for an empty range or all −∞.
template <typename Iterator>
double log_sum_exp(Iterator first, Iterator last) {
  if (first == last) return kLogZero;
  const double m = *std::max_element(first, last);
  if (m == kLogZero) return kLogZero;
  double s = 0.0;
  for (auto it = first; it != last; ++it) s += std::exp(*it - m);
  return m + std::log(s);
}

inline double log_sum_exp(const std::vector<double>& v) {
  return log_sum_exp(v.begin(), v.end());
}

/// Normalises log weights in place so that Σ e^{w_i} = 1; returns the log normaliser.
inline double normalize_log_weights(std::vector<double>& log_w) {
  const double z = log_sum_exp(log_w);
  for (double& w : log_w) w -= z;
  return z;
}

/// Effective sample size 1 / Σ w_i² of normalised log weights.
inline double effective_sample_size(const std::vector<double>& normalized_log_w) {
  double s = 0.0;
  for (double w : normalized_log_w) s += std::exp(2.0 * w);
  return s > 0.0 ? 1.0 / s : 0.0;
}

}  // namespace glmbslam
