#pragma once
// ACFR Victoria Park (../shared/data/README.md): odometry (aa3_dr.mat), GPS (aa3_gpsx.mat) and the tree
// detections per laser scan (VictoriaParkSinSincronizar.mat), read with libmatio through MatFile. All times
// are converted to seconds on the odometry clock (the files share one clock: aa3_dr `time` [ms] equals
// VictoriaParkSinSincronizar `time` [s] × 1000).
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::io {

/// Dead-reckoning samples (40 Hz): speed [m/s] and steering angle [rad] at time [s].
struct VictoriaParkOdometry {
  std::vector<double> time_s;
  std::vector<double> speed;
  std::vector<double> steering;
};

struct GpsFix {
  double time_s = 0.0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< (Lo_m, La_m) [m], local metric frame
};

/// One laser scan's tree detections: columns (range [m], bearing in the laser frame [rad], diameter [m]);
/// laser bearing 0 = right, π/2 = forward, π = left (subtract π/2 for the vehicle frame, left positive).
struct LaserScan {
  double time_s = 0.0;
  Eigen::Matrix3Xd detections;
};

/// GPS outlier filter (documented rule, README: 81 gaps over 1 s and ~41 jumps faster than the truck can
/// drive):
///  1. fixes are taken in time order; a fix whose implied speed from the last *accepted* fix exceeds
///     max_speed_mps (10 m/s; the truck's top speed is ~6.6 m/s) while that fix is at most max_gap_s (1 s)
///     old is rejected as a jump (so a spike is dropped, and after a step the fixes are rejected until
///     max_gap_s has passed since the last accepted one);
///  2. the accepted fixes are split into segments at gaps longer than max_gap_s; segments with fewer than
///     min_segment_fixes fixes (isolated fixes after a gap, which the speed test cannot validate) are
///     dropped.
struct GpsFilterOptions {
  double max_speed_mps = 10.0;
  double max_gap_s = 1.0;
  std::size_t min_segment_fixes = 3;
};

struct GpsFilterResult {
  std::vector<GpsFix> fixes;       ///< accepted fixes, time ordered
  std::size_t gaps = 0;            ///< gaps longer than max_gap_s in the raw sequence
  std::size_t jumps = 0;           ///< fixes rejected by the speed test
  std::size_t short_segments = 0;  ///< fixes dropped with too-short segments
};

GpsFilterResult filter_gps_outliers(const std::vector<GpsFix>& raw, const GpsFilterOptions& options = {});

struct VictoriaParkData {
  std::filesystem::path folder;
  VictoriaParkOdometry odometry;  ///< from aa3_dr.mat
  std::vector<GpsFix> gps_raw;    ///< from aa3_gpsx.mat, in file order
  GpsFilterResult gps;            ///< filtered with the default options
  std::vector<LaserScan> scans;   ///< from VictoriaParkSinSincronizar.mat (TLsr, zt)
};

/// File names inside a Victoria Park folder.
inline constexpr const char* kVictoriaParkOdometryFile = "aa3_dr.mat";
inline constexpr const char* kVictoriaParkGpsFile = "aa3_gpsx.mat";
inline constexpr const char* kVictoriaParkDetectionsFile = "VictoriaParkSinSincronizar.mat";

/// True when the folder holds the three files.
bool is_victoria_park_folder(const std::filesystem::path& folder);

/// Reads and validates the three files:
///  aa3_dr.mat: speed, steering, time — vectors of one common length n ≥ 2, time strictly increasing;
///  aa3_gpsx.mat: timeGps, Lo_m, La_m — vectors of one common length ≥ 1 (the evaluation's reference: when
///  the file is absent the data have no fixes, with a warning);
///  VictoriaParkSinSincronizar.mat: TLsr — vector, non-decreasing; zt — cell array with one cell per TLsr
///  entry, each 3×M (or empty), ranges ≥ 0.
/// Throws InputError naming the file and the variable.
VictoriaParkData read_victoria_park(const std::filesystem::path& folder);

}  // namespace glmbslam::io
