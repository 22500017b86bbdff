#include "io/victoria_park.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "io/mat_reader.hpp"

namespace glmbslam::io {

namespace {

std::vector<double> to_std(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

void require_same_length(const std::string& file, const std::string& name, Eigen::Index length,
                         Eigen::Index expected, const std::string& reference) {
  if (length != expected) {
    throw InputError(file, "variable '" + name + "' has " + std::to_string(length) + " elements but '" +
                               reference + "' has " + std::to_string(expected));
  }
}

VictoriaParkOdometry read_odometry(const std::filesystem::path& path) {
  const MatFile mat(path);
  const std::string file = path.string();
  const Eigen::VectorXd time = mat.read_vector("time");
  const Eigen::VectorXd speed = mat.read_vector("speed");
  const Eigen::VectorXd steering = mat.read_vector("steering");
  require_same_length(file, "speed", speed.size(), time.size(), "time");
  require_same_length(file, "steering", steering.size(), time.size(), "time");
  if (time.size() < 2) throw InputError(file, "variable 'time' must have at least 2 samples");
  for (Eigen::Index i = 1; i < time.size(); ++i) {
    if (!(time(i) > time(i - 1))) {
      throw InputError(file, "variable 'time' must increase strictly (sample " + std::to_string(i + 1) + ")");
    }
  }
  VictoriaParkOdometry odo;
  odo.time_s = to_std(time / 1000.0);
  odo.speed = to_std(speed);
  odo.steering = to_std(steering);
  return odo;
}

std::vector<GpsFix> read_gps(const std::filesystem::path& path) {
  const MatFile mat(path);
  const std::string file = path.string();
  const Eigen::VectorXd time = mat.read_vector("timeGps");
  const Eigen::VectorXd lo = mat.read_vector("Lo_m");
  const Eigen::VectorXd la = mat.read_vector("La_m");
  require_same_length(file, "Lo_m", lo.size(), time.size(), "timeGps");
  require_same_length(file, "La_m", la.size(), time.size(), "timeGps");
  if (time.size() < 1) throw InputError(file, "variable 'timeGps' is empty");
  std::vector<GpsFix> fixes(static_cast<std::size_t>(time.size()));
  for (Eigen::Index i = 0; i < time.size(); ++i) {
    fixes[static_cast<std::size_t>(i)].time_s = time(i) / 1000.0;
    fixes[static_cast<std::size_t>(i)].position = Eigen::Vector2d(lo(i), la(i));
  }
  return fixes;
}

std::vector<LaserScan> read_scans(const std::filesystem::path& path) {
  const MatFile mat(path);
  const std::string file = path.string();
  const Eigen::VectorXd tlsr = mat.read_vector("TLsr");
  for (Eigen::Index i = 1; i < tlsr.size(); ++i) {
    if (tlsr(i) < tlsr(i - 1)) {
      throw InputError(file, "variable 'TLsr' must not decrease (scan " + std::to_string(i + 1) + ")");
    }
  }
  const std::vector<Eigen::MatrixXd> zt = mat.read_cell_matrices("zt", 3, tlsr.size());
  std::vector<LaserScan> scans(zt.size());
  for (std::size_t k = 0; k < zt.size(); ++k) {
    scans[k].time_s = tlsr(static_cast<Eigen::Index>(k));
    scans[k].detections = zt[k];
    if (zt[k].cols() > 0 && zt[k].row(0).minCoeff() < 0.0) {
      throw InputError(file, "variable 'zt{" + std::to_string(k + 1) + "}' has a negative range");
    }
  }
  return scans;
}

}  // namespace

GpsFilterResult filter_gps_outliers(const std::vector<GpsFix>& raw, const GpsFilterOptions& o) {
  std::vector<GpsFix> sorted = raw;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const GpsFix& a, const GpsFix& b) { return a.time_s < b.time_s; });
  GpsFilterResult result;
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i].time_s - sorted[i - 1].time_s > o.max_gap_s) ++result.gaps;
  }
  std::vector<GpsFix> accepted;
  for (const GpsFix& f : sorted) {
    if (!f.position.allFinite() || !std::isfinite(f.time_s)) {
      ++result.jumps;
      continue;
    }
    if (!accepted.empty()) {
      const GpsFix& last = accepted.back();
      const double dt = f.time_s - last.time_s;
      if (dt <= 0.0) {  // duplicate time stamp: keep the first
        ++result.jumps;
        continue;
      }
      if (dt <= o.max_gap_s && (f.position - last.position).norm() / dt > o.max_speed_mps) {
        ++result.jumps;
        continue;
      }
    }
    accepted.push_back(f);
  }
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= accepted.size(); ++i) {
    if (i == accepted.size() || accepted[i].time_s - accepted[i - 1].time_s > o.max_gap_s) {
      if (i - begin >= o.min_segment_fixes) {
        result.fixes.insert(result.fixes.end(), accepted.begin() + static_cast<std::ptrdiff_t>(begin),
                            accepted.begin() + static_cast<std::ptrdiff_t>(i));
      } else {
        result.short_segments += i - begin;
      }
      begin = i;
    }
  }
  return result;
}

bool is_victoria_park_folder(const std::filesystem::path& folder) {
  return std::filesystem::is_regular_file(folder / kVictoriaParkOdometryFile) &&
         std::filesystem::is_regular_file(folder / kVictoriaParkGpsFile) &&
         std::filesystem::is_regular_file(folder / kVictoriaParkDetectionsFile);
}

VictoriaParkData read_victoria_park(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) throw InputError(folder.string(), "not a folder");
  VictoriaParkData data;
  data.folder = folder;
  data.odometry = read_odometry(folder / kVictoriaParkOdometryFile);
  // GPS is the reference, not an input: without it the run goes on unevaluated
  if (std::filesystem::exists(folder / kVictoriaParkGpsFile)) {
    data.gps_raw = read_gps(folder / kVictoriaParkGpsFile);
  } else {
    spdlog::warn("{}: not found; running without the GPS reference (no position RMSE)",
                 (folder / kVictoriaParkGpsFile).string());
  }
  data.gps = filter_gps_outliers(data.gps_raw);
  data.scans = read_scans(folder / kVictoriaParkDetectionsFile);
  return data;
}

}  // namespace glmbslam::io
