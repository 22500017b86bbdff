#include "app/victoria_park_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/victoria_park_data.hpp"
#include "app/victoria_park_report.hpp"
#include "core/atomic_file.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"
#include "eval/line_plot.hpp"
#include "eval/report.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::app {
namespace {

using Vec2List = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;

/// One estimate's files: trajectory<suffix>.txt, map<suffix>.txt / .pcd, gps_errors<suffix>.txt.
void write_estimate_files(const std::filesystem::path& out, const std::string& suffix,
                          const std::vector<double>& times, const VpStateList& poses,
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

Vec2List positions_of(const VpStateList& poses) {
  Vec2List positions;
  for (const auto& p : poses) positions.push_back(p.head<2>());
  return positions;
}

}  // namespace

void write_victoria_park_outputs(const std::filesystem::path& out, const VictoriaParkConfig& cfg,
                                 const RunOptions& options, const io::VictoriaParkData& data,
                                 const std::vector<io::GpsFix>& gps, const std::vector<double>& times,
                                 const VpRunRecord& rec, const io::GpsFilterResult& filt) {
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
  j["particles"] = victoria_park_particles(cfg);
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
    const VpRefinedEstimate& r = *rec.refined;
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
  const auto rmse_text = [](const GpsErrors& e) {  // "n/a" without GPS fixes near the scans
    char text[32];
    std::snprintf(text, sizeof text, std::isfinite(e.rmse_m) ? "%.3f m" : "n/a", e.rmse_m);
    return std::string(text);
  };
  std::printf(
      "victoria_park %s N=%d seed=%llu: frames %zu, position RMSE %s (%zu GPS fixes), %.3f ms/step "
      "(std %.3f), total %.2f s, ESS %.1f %%, resampling %.2f %%, %zu landmarks\n",
      cfg.algorithm.c_str(), static_cast<int>(j["particles"]), static_cast<unsigned long long>(cfg.rbpf.seed),
      rec.poses.size(), rmse_text(err).c_str(), err.error_m.size(), ms.mean, ms.stddev, rec.total_s,
      100.0 * ess_mean, j["resampling_percent"].get<double>(), rec.map.size());
  if (rec.refined)
    std::printf(
        "victoria_park refined (RFS-ML): position RMSE %s (%zu GPS fixes), %zu landmarks, %d EM rounds, "
        "%.2f s%s\n",
        rmse_text(err_refined).c_str(), err_refined.error_m.size(), rec.refined->map.size(),
        rec.refined->report.rounds, rec.refined->report.ms / 1000.0,
        rec.refined->report.stopped ? " (stopped early)" : "");
  std::fflush(stdout);
}

}  // namespace glmbslam::app
