#pragma once
// Wall-clock timing and summary statistics (median, p95) for per-stage timing reports.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace glmbslam {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// q-quantile (0 ≤ q ≤ 1) by linear interpolation; 0 for an empty sample.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

struct SampleSummary {
  double mean = 0.0;
  double stddev = 0.0;
  double median = 0.0;
  double p95 = 0.0;
};

inline SampleSummary summarize(const std::vector<double>& v) {
  SampleSummary s;
  if (v.empty()) return s;
  double sum = 0.0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.stddev = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
  s.median = quantile(v, 0.5);
  s.p95 = quantile(v, 0.95);
  return s;
}

}  // namespace glmbslam
