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
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "app/baseline_filters.hpp"
#include "app/global_options.hpp"
#include "app/run_options.hpp"
#include "app/victoria_park_config.hpp"
#include "app/victoria_park_data.hpp"
#include "app/victoria_park_ml.hpp"
#include "app/victoria_park_report.hpp"
#include "backend/models/ackermann_motion.hpp"
#include "backend/models/victoria_park_measurement.hpp"
#include "backend/phd/phd_slam.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "eval/line_plot.hpp"
#include "eval/report.hpp"
#include "io/pcd_writer.hpp"
#include "io/victoria_park.hpp"

namespace glmbslam::app {
namespace {

using Motion = backend::AckermannMotion;
using Meas = backend::VictoriaParkMeasurement;
using Vec2List = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;

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

/// --refine ml: the RFS-ML refinement of the filter's estimate, kept beside it.
struct RefinedEstimate {
  std::vector<Motion::State, Eigen::aligned_allocator<Motion::State>> poses;
  std::vector<io::MapPoint> map;
  backend::MlSlamReport report;
};

struct RunRecord {
  std::vector<Motion::State, Eigen::aligned_allocator<Motion::State>> poses;
  std::vector<double> ms, ess;
  int resamples = 0;
  double total_s = 0.0;
  std::size_t steps_requested = 0;      ///< steps of the run; more than poses.size() when interrupted
  bool refinement_interrupted = false;  ///< the RFS-ML solve was stopped early (its last round's estimate)
  std::vector<io::MapPoint> map;
  std::optional<RefinedEstimate> refined;  ///< --refine ml
};

template <class Filter>
RunRecord run_filter(Filter& filter, const std::vector<Motion::Control>& controls,
                     const std::vector<VpMeasurementSet>& measurements, int particles) {
  RunRecord rec;
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
                   const std::vector<VpMeasurementSet>& measurements, RunRecord& rec) {
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
  RefinedEstimate out;
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

/// One estimate's files: trajectory<suffix>.txt, map<suffix>.txt / .pcd, gps_errors<suffix>.txt.
void write_estimate_files(const std::filesystem::path& out, const std::string& suffix,
                          const std::vector<double>& times,
                          const std::vector<Motion::State, Eigen::aligned_allocator<Motion::State>>& poses,
                          const std::vector<io::MapPoint>& landmarks, const GpsErrors& err) {
  std::ostringstream traj;
  traj.precision(10);
  for (std::size_t k = 0; k < poses.size(); ++k)
    traj << times[k] << ' ' << poses[k](0) << ' ' << poses[k](1) << ' ' << poses[k](2) << '\n';
  write_text_file_atomically(out / ("trajectory" + suffix + ".txt"),
                             [&](std::ostream& os) { os << traj.str(); });
  std::ostringstream map;
  map.precision(10);
  for (const auto& p : landmarks)
    map << p.position.x() << ' ' << p.position.y() << ' ' << p.existence << '\n';
  write_text_file_atomically(out / ("map" + suffix + ".txt"), [&](std::ostream& os) { os << map.str(); });
  std::ostringstream errors;
  errors.precision(10);
  for (std::size_t i = 0; i < err.error_m.size(); ++i)
    errors << err.scan_time[i] << ' ' << err.error_m[i] << '\n';
  write_text_file_atomically(out / ("gps_errors" + suffix + ".txt"),
                             [&](std::ostream& os) { os << errors.str(); });
  io::write_pcd_map((out / ("map" + suffix + ".pcd")).string(), landmarks);
}

Vec2List positions_of(const std::vector<Motion::State, Eigen::aligned_allocator<Motion::State>>& poses) {
  Vec2List positions;
  for (const auto& p : poses) positions.push_back(p.head<2>());
  return positions;
}

void write_outputs(const std::filesystem::path& out, const VictoriaParkConfig& cfg, const RunOptions& options,
                   const io::VictoriaParkData& data, const std::vector<io::GpsFix>& gps,
                   const std::vector<double>& times, const RunRecord& rec, const io::GpsFilterResult& filt) {
  ensure_writable_directory(out);
  const Vec2List positions = positions_of(rec.poses);
  const GpsErrors err = gps_errors(gps, times, positions, cfg.gps_match_window_s);
  std::vector<io::GpsFix> raw = data.gps_raw;
  std::stable_sort(raw.begin(), raw.end(), [](const auto& a, const auto& b) { return a.time_s < b.time_s; });
  const GpsErrors err_raw = gps_errors(raw, times, positions, cfg.gps_match_window_s);
  GpsErrors err_refined;
  const SampleSummary ms = summarize(rec.ms);
  double ess_mean = 0.0;
  for (double e : rec.ess) ess_mean += e;
  ess_mean = rec.ess.empty() ? 0.0 : ess_mean / static_cast<double>(rec.ess.size());
  const double frames = static_cast<double>(rec.poses.size());
  auto finite_or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };

  nlohmann::json j;
  j["dataset"] = options.dataset;
  j["format"] = "victoria_park";
  j["algorithm"] = cfg.algorithm;
  j["refine"] = options.refine;
  j["particles"] = cfg.algorithm == "deadreckoning" ? 1 : cfg.rbpf.particles;
  j["seed"] = cfg.rbpf.seed;
  j["threads"] = thread_count();
  j["frames"] = rec.poses.size();
  j["frames_requested"] = rec.steps_requested;
  j["interrupted"] = rec.poses.size() < rec.steps_requested || rec.refinement_interrupted;
  j["duration_s"] = times.empty() ? 0.0 : times.back() - data.odometry.time_s.front();
  j["position_rmse_m"] = finite_or_null(err.rmse_m);
  j["gps_fixes_used"] = err.error_m.size();
  j["position_rmse_raw_gps_m"] = finite_or_null(err_raw.rmse_m);
  j["gps_fixes_used_raw"] = err_raw.error_m.size();
  j["gps_filter"] = {{"raw_fixes", data.gps_raw.size()},
                     {"accepted_fixes", filt.fixes.size()},
                     {"gaps_over_max_gap", filt.gaps},
                     {"jumps_rejected", filt.jumps},
                     {"short_segment_fixes_dropped", filt.short_segments},
                     {"max_speed_mps", cfg.gps.max_speed_mps},
                     {"max_gap_s", cfg.gps.max_gap_s},
                     {"min_segment_fixes", cfg.gps.min_segment_fixes},
                     {"match_window_s", cfg.gps_match_window_s}};
  j["ms_per_step"] = {{"mean", ms.mean}, {"std", ms.stddev}, {"median", ms.median}, {"p95", ms.p95}};
  j["total_s"] = rec.total_s;
  j["ess_percent"] = 100.0 * ess_mean;
  j["resampling_percent"] = frames > 0 ? 100.0 * rec.resamples / frames : 0.0;
  j["map"] = {{"landmarks", rec.map.size()}};
  j["clutter_rate"] = cfg.clutter_rate;
  if (rec.refined) {
    const RefinedEstimate& r = *rec.refined;
    const Vec2List refined_positions = positions_of(r.poses);
    err_refined = gps_errors(gps, times, refined_positions, cfg.gps_match_window_s);
    const GpsErrors refined_raw = gps_errors(raw, times, refined_positions, cfg.gps_match_window_s);
    j["refined"] = {{"position_rmse_m", finite_or_null(err_refined.rmse_m)},
                    {"gps_fixes_used", err_refined.error_m.size()},
                    {"position_rmse_raw_gps_m", finite_or_null(refined_raw.rmse_m)},
                    {"gps_fixes_used_raw", refined_raw.error_m.size()},
                    {"landmarks", r.map.size()},
                    {"solve_s", r.report.ms / 1000.0},
                    {"rounds", r.report.rounds},
                    {"births", r.report.births},
                    {"deaths", r.report.deaths},
                    {"merges", r.report.merges},
                    {"log_likelihood_gain", r.report.final_log_likelihood - r.report.initial_log_likelihood},
                    {"interrupted", r.report.stopped}};
  }
  eval::write_json_file((out / "metrics.json").string(), j);
  VictoriaParkReportInput report;
  report.gps = &gps;
  report.map = &rec.map;
  report.error_time_s = &err.scan_time;
  report.error_m = &err.error_m;
  report.ess = &rec.ess;
  report.ms = &rec.ms;
  for (const auto& p : rec.poses) report.x.push_back(p(0)), report.y.push_back(p(1));
  if (rec.refined) {
    report.refined_map = &rec.refined->map;
    report.refined_error_m = &err_refined.error_m;
    report.refined_error_time_s = &err_refined.scan_time;
    for (const auto& p : rec.refined->poses)
      report.refined_x.push_back(p(0)), report.refined_y.push_back(p(1));
  }
  write_victoria_park_report((out / "report.html").string(), report, j);

  write_estimate_files(out, "", times, rec.poses, rec.map, err);
  if (rec.refined)
    write_estimate_files(out, "_refined", times, rec.refined->poses, rec.refined->map, err_refined);

  if (cfg.write_plot) {
    auto metres = [](double v) { return std::isfinite(v) ? std::to_string(v).substr(0, 5) + " m" : "n/a"; };
    eval::LinePlot plot("Victoria Park: " + cfg.algorithm +
                            ", N = " + std::to_string(static_cast<int>(j["particles"])) + ", position RMSE " +
                            metres(err.rmse_m) +
                            (rec.refined ? ", refined " + metres(err_refined.rmse_m) : ""),
                        "x (m)", "y (m)");
    std::vector<double> gx, gy, ex, ey, mx, my;
    for (const auto& f : gps) {
      gx.push_back(f.position.x());
      gy.push_back(f.position.y());
    }
    for (const auto& p : rec.poses) {
      ex.push_back(p(0));
      ey.push_back(p(1));
    }
    for (const auto& p : rec.map) {
      mx.push_back(p.position.x());
      my.push_back(p.position.y());
    }
    plot.add_series(gx, gy, eval::colours::kBlack, "GPS", eval::SeriesStyle::kMarkers, 1);
    plot.add_series(ex, ey, eval::colours::kRed, rec.refined ? "filter" : "estimate",
                    eval::SeriesStyle::kLine, 2);
    if (!mx.empty()) plot.add_series(mx, my, eval::colours::kBlue, "map", eval::SeriesStyle::kMarkers, 2);
    if (rec.refined) {
      std::vector<double> rx, ry;
      for (const auto& p : rec.refined->poses) rx.push_back(p(0)), ry.push_back(p(1));
      plot.add_series(rx, ry, eval::colours::kGreen, "refined (RFS-ML)", eval::SeriesStyle::kLine, 2);
    }
    plot.set_equal_aspect(true);
    plot.save_png((out / "trajectory.png").string(), 1000, 1000);
  }
  std::printf(
      "victoria_park %s N=%d seed=%llu: frames %zu, position RMSE %.3f m (%zu GPS fixes), %.3f ms/step "
      "(std %.3f), total %.2f s, ESS %.1f %%, resampling %.2f %%, %zu landmarks\n",
      cfg.algorithm.c_str(), static_cast<int>(j["particles"]), static_cast<unsigned long long>(cfg.rbpf.seed),
      rec.poses.size(), err.rmse_m, err.error_m.size(), ms.mean, ms.stddev, rec.total_s, 100.0 * ess_mean,
      j["resampling_percent"].get<double>(), rec.map.size());
  if (rec.refined)
    std::printf(
        "victoria_park refined (RFS-ML): position RMSE %.3f m (%zu GPS fixes), %zu landmarks, %d EM rounds, "
        "%.2f s%s\n",
        err_refined.rmse_m, err_refined.error_m.size(), rec.refined->map.size(), rec.refined->report.rounds,
        rec.refined->report.ms / 1000.0, rec.refined->report.stopped ? " (stopped early)" : "");
  std::fflush(stdout);
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
          "--algorithm for Victoria Park must be glmb2, glmb1, glmb-mh, phd1, phd3, lmb, lmb1, fastslam2 or "
          "deadreckoning (got '" +
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
               cfg.rbpf.particles, cfg.rbpf.seed);
  RunRecord rec;
  set_graceful_interrupts(true);  // SIGINT/SIGTERM: stop at the next scan and write the steps done
  if (!options.refine.empty() && options.refine != "ml")
    throw ConfigError("--refine must be ml (got '" + options.refine + "')");
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
  write_outputs(options.out_dir, cfg, options, data, filt.fixes, times, rec, filt);
  return 0;
}

}  // namespace glmbslam::app
