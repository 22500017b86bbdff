#include "app/victoria_park_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/random.hpp"

namespace glmbslam::app {

std::vector<backend::AckermannMotion::Control> build_scan_controls(const io::VictoriaParkOdometry& odometry,
                                                                   double start_time,
                                                                   const std::vector<double>& scan_times) {
  const std::vector<double>& t = odometry.time_s;
  const std::size_t n = t.size();
  std::vector<backend::AckermannMotion::Control> controls;
  controls.reserve(scan_times.size());
  // index of the sample in force at time `time`: last i with t[i] ≤ time (0 if none)
  auto in_force = [&](double time) -> std::size_t {
    const auto it = std::upper_bound(t.begin(), t.end(), time);
    return it == t.begin() ? 0 : static_cast<std::size_t>(it - t.begin()) - 1;
  };
  double prev = start_time;
  std::vector<Eigen::Vector3d> pieces;
  for (const double tk : scan_times) {
    pieces.clear();
    if (tk > prev && n > 0) {
      std::size_t i = in_force(prev);
      double from = prev;
      while (from < tk) {
        const double next = (i + 1 < n) ? std::min(t[i + 1], tk) : tk;
        if (next > from) pieces.emplace_back(odometry.speed[i], odometry.steering[i], next - from);
        from = next;
        if (i + 1 < n && t[i + 1] <= from) ++i;  // past the last sample: it is held until tk
      }
    }
    backend::AckermannMotion::Control u(3, static_cast<Eigen::Index>(pieces.size()));
    for (std::size_t p = 0; p < pieces.size(); ++p) u.col(static_cast<Eigen::Index>(p)) = pieces[p];
    controls.push_back(std::move(u));
    prev = std::max(prev, tk);
  }
  return controls;
}

VpMeasurementSet scan_detections(const io::LaserScan& scan, double max_range, double half_fov) {
  VpMeasurementSet Z;
  for (Eigen::Index j = 0; j < scan.detections.cols(); ++j) {
    const double r = scan.detections(0, j);
    const double b = wrap_angle(scan.detections(1, j) - 0.5 * M_PI);
    const double d = scan.detections(2, j);
    if (r <= max_range && std::abs(b) <= half_fov && d >= 0.0) Z.emplace_back(r, b);
  }
  return Z;
}

void append_clutter(const ClutterOptions& options, std::size_t scan_index, VpMeasurementSet& Z) {
  if (options.rate <= 0.0) return;
  RandomStream rng(options.seed, kClutterStream + scan_index);
  const int count = rng.poisson(options.rate);
  for (int c = 0; c < count; ++c) {
    const double r = rng.uniform(0.0, options.max_range);
    const double b = rng.uniform(-options.half_fov, options.half_fov);
    Z.emplace_back(r, b);
  }
}

GpsErrors gps_errors(const std::vector<io::GpsFix>& fixes, const std::vector<double>& scan_times,
                     const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& positions,
                     double window_s) {
  GpsErrors out;
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < scan_times.size() && k < positions.size(); ++k) {
    const double tk = scan_times[k];
    const auto it = std::lower_bound(fixes.begin(), fixes.end(), tk,
                                     [](const io::GpsFix& f, double t) { return f.time_s < t; });
    const io::GpsFix* best = nullptr;
    double best_dt = std::numeric_limits<double>::infinity();
    if (it != fixes.end()) {
      best = &*it;
      best_dt = std::abs(it->time_s - tk);
    }
    if (it != fixes.begin() && std::abs(std::prev(it)->time_s - tk) < best_dt) {
      best = &*std::prev(it);
      best_dt = std::abs(best->time_s - tk);
    }
    if (best == nullptr || !(best_dt <= window_s)) continue;
    const double e = (positions[k] - best->position).norm();
    out.scan_time.push_back(tk);
    out.error_m.push_back(e);
    sum_sq += e * e;
  }
  out.rmse_m = out.error_m.empty() ? std::numeric_limits<double>::quiet_NaN()
                                   : std::sqrt(sum_sq / static_cast<double>(out.error_m.size()));
  return out;
}

}  // namespace glmbslam::app
