#include "frontend/pixel_noise_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace glmbslam::frontend {

namespace {

constexpr double kChi2_3Median = 2.365973884;  // median of χ²₃
constexpr double kOutlier = 400.0;             // (20 σ)²: a residual this far out is a wrong match

/// P(χ²₃ ≤ x).
double chi2_3_cdf(double x) {
  return std::erf(std::sqrt(x / 2.0)) - std::sqrt(2.0 * x / M_PI) * std::exp(-x / 2.0);
}

}  // namespace

double chi2_3_quantile(double p) {
  double lo = 0.0, hi = 100.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_3_cdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double coverage_chi2_3_scale(std::vector<double> v, double coverage) {
  if (v.empty()) return std::nan("");
  auto quantile = [&v](double p) {
    const auto k = static_cast<std::ptrdiff_t>(std::floor(p * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[static_cast<std::size_t>(k)];
  };
  const double core = quantile(0.5) / kChi2_3Median;
  // gross outliers (wrong matches) beyond kOutlier times the median scale leave first
  v.erase(std::remove_if(v.begin(), v.end(), [&](double x) { return !(x <= kOutlier * core); }), v.end());
  if (v.empty()) return core;
  return quantile(coverage) / chi2_3_quantile(coverage);
}

PixelNoiseEstimator::PixelNoiseEstimator(const PixelNoiseOptions& options)
    : options_(options),
      sigma_(std::clamp(options.initial, options.floor, options.ceiling)),
      raw_sigma_(std::nan("")) {}

bool PixelNoiseEstimator::add_frame(const std::vector<double>& unit_chi2, int fit_dimensions,
                                    double median_flow_px) {
  const std::size_t n = unit_chi2.size();
  if (!(median_flow_px >= options_.min_flow_px) || n == 0 || fit_dimensions <= 12) return false;
  // the fitted pose absorbs 6 of the fit's residual dimensions
  const double dof_correction = fit_dimensions / (fit_dimensions - 6.0);
  std::vector<double> corrected;
  corrected.reserve(n);
  for (double s : unit_chi2) {
    if (std::isfinite(s)) corrected.push_back(s * dof_correction);
  }
  pooled_ += corrected.size();
  frames_.push_back(std::move(corrected));
  while (static_cast<int>(frames_.size()) > options_.window_frames) {
    pooled_ -= frames_.front().size();
    frames_.pop_front();
  }
  if (pooled_ >= static_cast<std::size_t>(options_.min_samples)) {
    std::vector<double> all;
    all.reserve(pooled_);
    for (const auto& f : frames_) all.insert(all.end(), f.begin(), f.end());
    raw_sigma_ = std::sqrt(coverage_chi2_3_scale(std::move(all), options_.coverage));
    sigma_ = std::clamp(raw_sigma_, options_.floor, options_.ceiling);
  }
  return true;
}

}  // namespace glmbslam::frontend
