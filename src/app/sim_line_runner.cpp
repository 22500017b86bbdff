#include "app/sim_line_runner.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <sstream>
#include <vector>

#include <spdlog/spdlog.h>

#include "app/sample_summary_json.hpp"
#include "backend/mlslam/line_ml_slam.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "eval/line_plot.hpp"
#include "eval/ospa.hpp"
#include "eval/report.hpp"
#include "sim/scenario_paper004_line.hpp"

namespace glmbslam::app {

namespace {

using json = nlohmann::json;
using backend::LineMlSlam;
constexpr double kOspaC = 1.0, kOspaP = 1.0;  // metres on the line; landmarks are ~1 m apart

struct LineRun {
  std::vector<double> estimates, map;
  std::vector<double> abs_error;  ///< |x̂_k − x_k| per step
  double squared_error = 0.0;     ///< Σ_k (x̂_k − x_k)²
  double rmse = 0.0, dead_reckoning_rmse = 0.0, log_likelihood = 0.0, ms = 0.0, map_ospa = 0.0;
  int rounds = 0, cardinality_error = 0;
};

eval::PointSet point_set(const std::vector<double>& v) {
  eval::PointSet p(1, static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) p(0, static_cast<Eigen::Index>(i)) = v[i];
  return p;
}

LineRun solve_run(const sim::LineScenario& s, const backend::MlSlamConfig& config) {
  backend::LineMotionConfig mc;
  mc.variance = s.odometry_variance;
  backend::LineSensorConfig sc;
  sc.variance = s.measurement_variance;
  sc.min_range = s.min_range;
  sc.max_range = s.max_range;
  sc.p_detect_inside = s.detection_probability;
  sc.clutter_rate = std::max(s.clutter_rate, 1e-9);  // κ > 0: the RFS likelihood needs a clutter density
  const LineMlSlam slam(backend::LineMotion(mc), backend::LineMeasurementModel(sc), config);
  LineMlSlam::ControlList u;
  std::vector<LineMlSlam::MeasurementSet> Z;
  for (double v : s.controls) u.push_back(backend::LinePose::Constant(v));
  for (const auto& z : s.measurements) {
    Z.emplace_back();
    for (double v : z) Z.back().push_back(LineMlSlam::Measurement::Constant(v));
  }
  LineMlSlam::PoseList x;
  LineMlSlam::LandmarkList m;
  const backend::MlSlamReport r =
      slam.solve_from_odometry(backend::LinePose::Constant(s.poses.front()), u, Z, x, m);
  LineRun out;
  double se_dr = 0.0, dr = s.poses.front();
  for (std::size_t k = 0; k < s.steps(); ++k) {
    if (k > 0) dr += s.controls[k];
    out.estimates.push_back(x[k](0));
    out.abs_error.push_back(std::abs(x[k](0) - s.poses[k]));
    out.squared_error += std::pow(x[k](0) - s.poses[k], 2);
    se_dr += std::pow(dr - s.poses[k], 2);
  }
  const double K = static_cast<double>(s.steps());
  out.rmse = std::sqrt(out.squared_error / K);
  out.dead_reckoning_rmse = std::sqrt(se_dr / K);
  for (const auto& l : m) out.map.push_back(l(0));
  // the landmarks the sensor could see at some step
  std::vector<double> seen;
  for (double l : s.landmarks) {
    bool in_view = false;
    for (double p : s.poses) in_view = in_view || (l - p >= s.min_range && l - p <= s.max_range);
    if (in_view) seen.push_back(l);
  }
  out.map_ospa = eval::ospa(point_set(seen), point_set(out.map), kOspaC, kOspaP).distance;
  out.cardinality_error = static_cast<int>(out.map.size()) - static_cast<int>(seen.size());
  out.log_likelihood = r.final_log_likelihood;
  out.ms = r.ms;
  out.rounds = r.rounds;
  return out;
}

void write_plots(const std::filesystem::path& dir, const sim::LineScenario& s0, const LineRun& r0,
                 const std::vector<double>& error_per_step, const SimOptions& o,
                 const std::string& association) {
  const std::string tag = o.scenario + " " + o.algorithm + " (" + association + ")";
  std::vector<double> steps(s0.steps());
  for (std::size_t k = 0; k < steps.size(); ++k) steps[k] = static_cast<double>(k);
  {
    eval::LinePlot plot("Mean absolute position error over " + std::to_string(o.runs) + " runs (" + tag + ")",
                        "time step", "error [m]");
    plot.add_series(steps, error_per_step, eval::colours::kBlue, "|x - x_true|");
    plot.set_include_zero_y(true);
    plot.save_png((dir / "position_error.png").string());
  }
  {
    eval::LinePlot plot("Trajectory and map, run " + std::to_string(o.first_run) + " (" + tag + ")",
                        "time step", "x [m]");
    std::vector<double> dr{s0.poses.front()};
    for (std::size_t k = 1; k < s0.steps(); ++k) dr.push_back(dr.back() + s0.controls[k]);
    plot.add_series(steps, s0.poses, eval::colours::kRed, "ground truth");
    plot.add_series(steps, r0.estimates, eval::colours::kGreen, "estimate");
    plot.add_series(steps, dr, eval::colours::kGrey, "dead reckoning");
    const double last = steps.empty() ? 0.0 : steps.back();
    plot.add_series(std::vector<double>(s0.landmarks.size(), last), s0.landmarks, eval::colours::kBlack,
                    "landmarks", eval::SeriesStyle::kMarkers);
    plot.add_series(std::vector<double>(r0.map.size(), last), r0.map, eval::colours::kRed, "map estimate",
                    eval::SeriesStyle::kMarkers);
    plot.save_png((dir / "trajectory_map.png").string());
  }
}

}  // namespace

void set_paper004_line_defaults(backend::MlSlamConfig& c) {
  c.incremental_steps = 1;
  c.initial_pose_search = 61;
}

json run_line_simulation(const SimOptions& o, const backend::MlSlamConfig& config) {
  const std::size_t R = static_cast<std::size_t>(o.runs);
  std::vector<LineRun> runs(R);
  std::vector<char> finished(R, 0);
  std::vector<std::exception_ptr> errors(R);
  auto scenario_of = [&](std::size_t r) {
    return sim::make_paper004_line_scenario({o.clutter, static_cast<std::uint64_t>(o.first_run) + r});
  };
  set_graceful_interrupts(true);  // SIGINT/SIGTERM: no new run starts
  parallel_for(R, [&](std::size_t r) {
    if (interrupt_requested()) return;
    try {
      runs[r] = solve_run(scenario_of(r), config);
      finished[r] = 1;
    } catch (...) {
      errors[r] = std::current_exception();
    }
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);

  const sim::LineScenario s0 = scenario_of(0);
  std::vector<double> rmse, dr_rmse, card, ospa, ms, rounds, ll, error_per_step(s0.steps(), 0.0);
  std::vector<int> indices;
  double se = 0.0, n = 0.0;
  for (std::size_t r = 0; r < R; ++r) {
    if (finished[r] == 0) continue;
    const LineRun& run = runs[r];
    indices.push_back(o.first_run + static_cast<int>(r));
    rmse.push_back(run.rmse);
    dr_rmse.push_back(run.dead_reckoning_rmse);
    card.push_back(run.cardinality_error);
    ospa.push_back(run.map_ospa);
    ms.push_back(run.ms);
    rounds.push_back(run.rounds);
    ll.push_back(run.log_likelihood);
    for (std::size_t k = 0; k < run.abs_error.size(); ++k) error_per_step[k] += run.abs_error[k];
    se += run.squared_error;
    n += static_cast<double>(run.abs_error.size());
  }
  const double done = static_cast<double>(indices.size());
  for (double& e : error_per_step) e = done > 0.0 ? e / done : 0.0;
  json m;
  m["scenario"] = o.scenario;
  m["algorithm"] = o.algorithm;
  m["association"] = config.association;
  m["runs"] = indices.size();
  m["runs_requested"] = R;
  m["run_indices"] = indices;
  m["interrupted"] = indices.size() < R;
  m["clutter_rate"] = s0.clutter_rate;
  m["steps"] = s0.steps();
  m["position_rmse_m"] = n > 0.0 ? std::sqrt(se / n) : 0.0;
  m["position_rmse_per_run_m"] = summary_json(rmse);
  m["position_rmse_each_run_m"] = rmse;
  m["position_error_per_step_m"] = error_per_step;
  m["max_position_error_m"] =
      error_per_step.empty() ? 0.0 : *std::max_element(error_per_step.begin(), error_per_step.end());
  m["dead_reckoning_rmse_per_run_m"] = summary_json(dr_rmse);
  m["cardinality_error"] = summary_json(card);
  m["map_ospa"] = json{{"c_m", kOspaC}, {"p", kOspaP}, {"distance_m", summary_json(ospa)}};
  m["ml"] = json{{"ms_per_run", summary_json(ms)},
                 {"rounds_per_run", summary_json(rounds)},
                 {"log_likelihood_each_run", ll}};
  const std::filesystem::path dir(o.out_dir);
  if (o.plots && finished[0] != 0) write_plots(dir, s0, runs[0], error_per_step, o, config.association);
  eval::write_json_file((dir / "metrics.json").string(), m);
  return m;
}

std::string summarize_line_simulation(const json& m) {
  if (m["runs"].get<int>() == 0) return "sim interrupted before any run finished (metrics.json says so)";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(4);
  s << m["scenario"].get<std::string>() << " " << m["algorithm"].get<std::string>() << " ("
    << m["association"].get<std::string>() << ") runs=" << m["runs"].get<int>()
    << " clutter=" << m["clutter_rate"].get<double>() << ": position RMSE "
    << m["position_rmse_m"].get<double>() << " m (dead reckoning "
    << m["dead_reckoning_rmse_per_run_m"]["mean"].get<double>() << " m), largest mean error per step "
    << m["max_position_error_m"].get<double>() << " m, map OSPA "
    << m["map_ospa"]["distance_m"]["mean"].get<double>() << " m, cardinality error "
    << m["cardinality_error"]["mean"].get<double>() << ", " << m["ml"]["ms_per_run"]["mean"].get<double>()
    << " ms per run";
  if (m.value("interrupted", false))
    s << " (interrupted: " << m["runs"].get<int>() << " of " << m["runs_requested"].get<int>() << " runs)";
  return s.str();
}

}  // namespace glmbslam::app
