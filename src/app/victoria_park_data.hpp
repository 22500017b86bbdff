#pragma once
// Victoria Park filter inputs (../shared/data/README.md, paper 003 Sec. VI-B protocol): per-scan Ackermann
// controls integrated from the 40 Hz odometry, per-scan measurement sets (tree detections in the vehicle
// frame, restricted to the field of view, plus seeded artificial Poisson clutter), and the GPS evaluation.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "backend/models/ackermann_motion.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "io/victoria_park.hpp"

namespace glmbslam::app {

using VpMeasurementSet = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;

/// Controls for the scan times t_1 < t_2 < …, starting at time t_0 = `start_time`: the control of step k
/// integrates [t_{k−1}, t_k] with the odometry held between samples (zero-order hold): the sample in force at
/// t_{k−1} (the last one at or before it; the first sample if none) until the next sample time, then each
/// sample inside (t_{k−1}, t_k) until the next one or t_k. Columns (v, α, dt); zero-length pieces are
/// dropped.
std::vector<backend::AckermannMotion::Control> build_scan_controls(const io::VictoriaParkOdometry& odometry,
                                                                   double start_time,
                                                                   const std::vector<double>& scan_times);

struct ClutterOptions {
  double rate = 5.0;                      ///< λ, mean clutter points per scan (0 = none)
  double max_range = 50.0;                ///< clutter range ~ U[0, max_range)
  double half_fov = 85.0 * M_PI / 180.0;  ///< clutter bearing ~ U[−half_fov, half_fov)
  std::uint64_t seed = 0;                 ///< stream (seed, 0xC1u77e7 + scan index)
};

/// Real detections of one scan in the vehicle frame: (range, laser bearing − π/2), keeping those with
/// range ≤ max_range, |bearing| ≤ half_fov and diameter ≥ 0 (the published protocol's field of view).
VpMeasurementSet scan_detections(const io::LaserScan& scan, double max_range, double half_fov);

/// Appends Poisson(λ) clutter points drawn uniformly in (range, bearing) over the field of view, from the
/// stream (options.seed, kClutterStream + scan_index): the same (seed, scan) always gives the same clutter.
void append_clutter(const ClutterOptions& options, std::size_t scan_index, VpMeasurementSet& Z);

inline constexpr std::uint64_t kClutterStream = 0xC1077E7ULL << 20;

/// Position errors against GPS (published protocol): for each step the GPS fix nearest in time to the scan;
/// used when |t_gps − t_scan| ≤ window_s. Fixes must be time ordered.
struct GpsErrors {
  std::vector<double> scan_time;  ///< per used fix
  std::vector<double> error_m;    ///< ‖p̂ − p_gps‖
  double rmse_m = 0.0;            ///< sqrt(mean error²) (NaN if none)
};
GpsErrors gps_errors(const std::vector<io::GpsFix>& fixes, const std::vector<double>& scan_times,
                     const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& positions,
                     double window_s);

}  // namespace glmbslam::app
