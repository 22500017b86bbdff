// `glmbslam run PATH_TO_victoria_park/` (run_options.hpp): the Victoria Park benchmark of paper 003
// (Sec. VI-B) with δ-GLMB-SLAM (glmb2 = optimal-kernel proposal, glmb1 = prior proposal, glmb-mh = the
// multi-hypothesis importance density of paper 003, backend/rbpf/mh_proposal.hpp), RB-PHD-SLAM 1.0 (phd1,
// backend/phd), PHD-SLAM 3.0 (phd3 = the GM-PHD map with the multi-hypothesis importance density) or dead
// reckoning.
//
// Steps: one per laser scan of VictoriaParkSinSincronizar.mat (scans with no tree detection are skipped when
// skip_empty_scans, as in the published protocol's code); the control of a step integrates the 40 Hz odometry
// between the scan times (victoria_park_data.hpp); the measurement set = the detections in the field of view
// (bearing − π/2) + Poisson(λ) artificial clutter uniform in (range, bearing) over the field of view, drawn
// from (rbpf.seed, scan index).
//
// Outputs in --out:
//   metrics.json     position_rmse_m (estimate at each scan vs the GPS fix nearest in time when within
//                    gps_match_window_s = 25 ms, after the reader's outlier filter), gps_fixes_used, the same
//                    against the unfiltered GPS (position_rmse_raw_gps_m — what the reference code computes),
//                    ms_per_step {mean, std, median, p95}, total_s, ess_percent (mean ESS/N),
//                    resampling_percent, map.landmarks, frames, and the run settings;
//   trajectory.txt   one line per step "t x y phi" (scan time [s] on the odometry clock, laser position [m]
//   in
//                    the GPS frame, heading [rad]) of the estimate at that step (highest-weight particle);
//   map.txt          "x y existence" per landmark of the final map estimate; map.pcd the same as a PCD (z =
//   0); trajectory.png   GPS fixes, estimated trajectory and map (like paper 003 Fig. 4);
//   gps_errors.txt   "t error" per GPS fix used by position_rmse_m (scan time [s], ‖p̂ − p_gps‖ [m]).
// With --refine ml these are the filter's, and the RFS-ML refinement (paper 004) adds trajectory_refined.txt,
// map_refined.txt, map_refined.pcd, gps_errors_refined.txt (same formats) and a `refined` block in
// metrics.json (position_rmse_m, gps_fixes_used, the raw-GPS pair, landmarks, solve_s, rounds, births,
// deaths, merges, log_likelihood_gain, interrupted), with the refined path in trajectory.png and report.html.
// With --algorithm mlslam (standalone RFS-ML from the odometry) the main outputs are the ML solution's.
// SIGINT/SIGTERM stop the filter at the next scan: the outputs cover the steps done (no refinement),
// metrics.json says "interrupted": true (with frames_requested), and the exit code is 130/143
// (core/interrupt.hpp). During the RFS-ML solve they stop it at its next EM round: the outputs hold the last
// round's estimate (standalone mlslam: of the steps solved so far) and "interrupted" is true.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "app/baseline_filters.hpp"
#include "app/global_options.hpp"
#include "app/refine_flag.hpp"
#include "app/run_options.hpp"
#include "app/victoria_park_config.hpp"
#include "app/victoria_park_data.hpp"
#include "app/victoria_park_ml.hpp"
#include "app/victoria_park_outputs.hpp"
#include "app/victoria_park_record.hpp"
#include "backend/models/ackermann_motion.hpp"
#include "backend/models/victoria_park_measurement.hpp"
#include "backend/phd/phd_slam.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "io/victoria_park.hpp"

namespace glmbslam::app {
namespace {

using Motion = backend::AckermannMotion;
using Meas = backend::VictoriaParkMeasurement;

/// The noise-free motion model (the floor every SLAM filter must beat).
class DeadReckoning {
 public:
  struct Report {
    double ess = 1.0;
    bool resampled = false;
  };
  DeadReckoning(const Motion& motion, const Motion::State& x0) : motion_(motion), x_(x0) {}
  void step(const Motion::Control& u, const VpMeasurementSet& /*Z*/) { x_ = motion_.predict(x_, u); }
  const Motion::State& pose() const { return x_; }
  const Report& last_report() const { return report_; }
  std::vector<backend::LandmarkEstimate<Meas>, Eigen::aligned_allocator<backend::LandmarkEstimate<Meas>>>
  landmarks() const {
    return {};
  }

 private:
  Motion motion_;
  Motion::State x_;
  Report report_;
};

double landmark_existence(const backend::LandmarkEstimate<Meas>& l) {
  return l.existence;
}
double landmark_existence(const backend::GmPhdComponent<Meas>& c) {
  return c.weight;
}

template <class Filter>
VpRunRecord run_filter(Filter& filter, const std::vector<Motion::Control>& controls,
                       const std::vector<VpMeasurementSet>& measurements, int particles) {
  VpRunRecord rec;
  const std::size_t n = controls.size();
  rec.steps_requested = n;
  rec.poses.reserve(n);
  rec.ms.reserve(n);
  rec.ess.reserve(n);
  Stopwatch total;
  for (std::size_t k = 0; k < n && !interrupt_requested(); ++k) {
    Stopwatch w;
    filter.step(controls[k], measurements[k]);
    rec.ms.push_back(w.elapsed_ms());
    rec.poses.push_back(filter.pose());
    rec.ess.push_back(filter.last_report().ess / static_cast<double>(particles));
    rec.resamples += filter.last_report().resampled ? 1 : 0;
  }
  rec.total_s = total.elapsed_ms() / 1000.0;
  std::uint64_t index = 0;
  for (const auto& l : filter.landmarks()) {
    io::MapPoint p;
    p.position = Eigen::Vector3d(l.mean(0), l.mean(1), 0.0);
    p.label = index++;
    p.existence = std::clamp(landmark_existence(l), 0.0, 1.0);
    rec.map.push_back(p);
  }
  return rec;
}

/// --algorithm mlslam: the RFS-ML solution replaces the (dead-reckoning) record's trajectory and map;
/// --refine ml: the refinement of the filter's estimate goes beside it (rec.refined).
void refine_record(const Motion& motion, const Meas& model, const VictoriaParkConfig& cfg,
                   const std::vector<Motion::Control>& controls,
                   const std::vector<VpMeasurementSet>& measurements, VpRunRecord& rec) {
  const bool standalone = cfg.algorithm == "mlslam";
  VpPoseList poses(rec.poses.begin(), rec.poses.end());
  std::vector<Eigen::Vector2d> map;
  for (const auto& p : rec.map) map.push_back(p.position.head<2>());
  if (!standalone)
    spdlog::info("Victoria Park: RFS-ML refinement of {} steps, {} landmarks", poses.size(), map.size());
  const backend::MlSlamReport r = solve_victoria_park_ml(
      motion, model, cfg.ml, cfg.initial_pose, controls, measurements, standalone,
      [] { return interrupt_requested(); }, poses, map);
  rec.refinement_interrupted = r.stopped;
  VpRefinedEstimate out;
  out.report = r;
  out.poses.assign(poses.begin(), poses.end());
  for (const auto& m : map) {
    io::MapPoint p;
    p.position = Eigen::Vector3d(m(0), m(1), 0.0);
    p.label = out.map.size();
    p.existence = 1.0;
    out.map.push_back(p);
  }
  if (standalone) {
    rec.total_s += r.ms / 1000.0;
    rec.poses = std::move(out.poses);
    rec.map = std::move(out.map);
  } else {
    rec.refined = std::move(out);
  }
}

}  // namespace

int run_victoria_park(const RunOptions& options) {
  VictoriaParkConfig cfg = default_victoria_park_config();
  if (!options.config_file.empty()) load_victoria_park_config(options.config_file, cfg);
  if (options.particles) {
    if (*options.particles < 1) throw ConfigError("--particles must be at least 1");
    cfg.rbpf.particles = *options.particles;
  }
  if (options.seed) cfg.rbpf.seed = *options.seed;
  if (options.algorithm) {
    std::string a = *options.algorithm;
    if (a == "glmb_mh") a = "glmb-mh";  // the spelling of `glmbslam sim`
    if (a == "dr") a = "deadreckoning";
    if (a == "phd3_mh" || a == "phd-mh") a = "phd3";
    if (a != "glmb2" && a != "glmb1" && a != "glmb-mh" && a != "phd1" && a != "phd3" &&
        a != "deadreckoning" && a != "mlslam" && a != "lmb" && a != "lmb1" && a != "fastslam2")
      throw ConfigError(
          "--algorithm for Victoria Park must be glmb2, glmb1, glmb-mh, phd1, phd3, lmb, lmb1, fastslam2, "
          "mlslam or deadreckoning (got '" +
          a + "')");
    cfg.algorithm = a;
  }
  if (options.first_frame != 0)
    throw ConfigError("--frames for Victoria Park must start at 0 (the filter starts at the first GPS fix)");
  if (global_options().threads) cfg.threads = *global_options().threads;  // --threads wins over `threads:`
  if (cfg.threads > 0) set_thread_count(cfg.threads);
  cfg.rbpf.proposal = cfg.algorithm == "glmb1" ? "prior" : cfg.algorithm == "glmb-mh" ? "mh" : "optimal";

  const io::VictoriaParkData data = io::read_victoria_park(options.dataset);
  const io::GpsFilterResult filt = io::filter_gps_outliers(data.gps_raw, cfg.gps);

  // steps
  std::vector<double> times;
  std::vector<VpMeasurementSet> measurements;
  ClutterOptions clutter;
  clutter.rate = cfg.clutter_rate;
  clutter.max_range = cfg.measurement.max_range;
  clutter.half_fov = cfg.measurement.half_fov;
  clutter.seed = cfg.rbpf.seed;
  for (std::size_t s = 0; s < data.scans.size(); ++s) {
    if (cfg.skip_empty_scans && data.scans[s].detections.cols() == 0) continue;
    if (options.last_frame != 0 && times.size() >= options.last_frame) break;
    VpMeasurementSet Z = scan_detections(data.scans[s], cfg.measurement.max_range, cfg.measurement.half_fov);
    append_clutter(clutter, s, Z);
    times.push_back(data.scans[s].time_s);
    measurements.push_back(std::move(Z));
  }
  const std::vector<Motion::Control> controls =
      build_scan_controls(data.odometry, data.odometry.time_s.front(), times);

  const Motion motion(cfg.motion);
  const Meas model(cfg.measurement);
  spdlog::info("Victoria Park: {} steps over {:.1f} s, algorithm {}, {} particles, seed {}", times.size(),
               times.empty() ? 0.0 : times.back() - data.odometry.time_s.front(), cfg.algorithm,
               victoria_park_particles(cfg), cfg.rbpf.seed);
  VpRunRecord rec;
  set_graceful_interrupts(true);  // SIGINT/SIGTERM: stop at the next scan and write the steps done
  if (!options.refine.empty() && options.refine != "ml")
    throw ConfigError("--refine must be ml (got '" + options.refine + "')");
  if (options.refine == "ml" && cfg.algorithm == "mlslam") throw ConfigError(kMlslamTakesNoRefinement);
  if (cfg.algorithm == "deadreckoning" || cfg.algorithm == "mlslam") {
    DeadReckoning f(motion, cfg.initial_pose);
    rec = run_filter(f, controls, measurements, 1);
  } else if (cfg.algorithm == "phd1" || cfg.algorithm == "phd3") {
    backend::PhdConfig phd = cfg.algorithm == "phd3" ? cfg.phd3 : cfg.phd;
    phd.particles = cfg.rbpf.particles;
    phd.seed = cfg.rbpf.seed;
    phd.proposal = cfg.algorithm == "phd3" ? "mh" : "prior";
    backend::validate_phd_config(phd);
    backend::PhdSlam<Motion, Meas> f(motion, model, phd, cfg.initial_pose, cfg.mh);
    rec = run_filter(f, controls, measurements, phd.particles);
  } else if (is_baseline_algorithm(cfg.algorithm)) {
    rec = with_baseline_filter(
        cfg.algorithm, motion, model, cfg.rbpf, cfg.baselines, cfg.initial_pose,
        [&](auto& f) { return run_filter(f, controls, measurements, cfg.rbpf.particles); });
  } else {
    backend::GlmbSlam<Motion, Meas> f(motion, model, cfg.rbpf, cfg.initial_pose, cfg.mh);
    rec = run_filter(f, controls, measurements, cfg.rbpf.particles);
  }
  if ((cfg.algorithm == "mlslam" || options.refine == "ml") && !interrupt_requested())
    refine_record(motion, model, cfg, controls, measurements, rec);
  if (rec.poses.size() < times.size()) {
    spdlog::warn("Victoria Park: interrupted after {} of {} steps; writing their outputs", rec.poses.size(),
                 times.size());
    times.resize(rec.poses.size());
  }
  write_victoria_park_outputs(options.out_dir, cfg, options, data, filt.fixes, times, rec, filt);
  return 0;
}

}  // namespace glmbslam::app
