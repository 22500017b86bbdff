#include "app/sim_runner.hpp"

#include <filesystem>
#include <sstream>

#include "app/sim_filters.hpp"
#include "app/sim_line_runner.hpp"
#include "app/sim_metrics.hpp"
#include "app/sim_monte_carlo.hpp"
#include "app/sim_options_check.hpp"
#include "app/sim_outputs.hpp"
#include "app/sim_scenarios.hpp"
#include "eval/report.hpp"

namespace glmbslam::app {

namespace {
using json = nlohmann::json;
}  // namespace

json run_simulation(const SimOptions& options) {
  const SimFilters filters = load_sim_filters(options);
  const SimOptions o = with_filter_defaults(options, filters);
  check_sim_options(o);
  if (o.scenario == "paper004_1d") return run_line_simulation(o, filters.ml);
  const SimScenarios scenarios(o);
  const SimRuns runs = run_monte_carlo(o, filters, scenarios);
  if (runs.records.empty()) {
    const json m = no_runs_metrics(o, runs);
    eval::write_json_file((std::filesystem::path(o.out_dir) / "metrics.json").string(), m);
    return m;
  }
  // every run's poses are the same (phdslam3 regenerates only the measurements and odometry per run)
  const sim::Scenario2D truth = scenarios.of_run(runs.run_indices.front());
  const SimMetrics metrics = sim_metrics(o, runs, truth, scenarios.clutter_rate());
  write_sim_outputs(o, metrics, truth, runs.records.front());
  return metrics.json;
}

std::string summarize_simulation(const json& m) {
  if (m.value("scenario", "") == "paper004_1d") return summarize_line_simulation(m);
  if (m["runs"].get<int>() == 0) return "sim interrupted before any run finished (metrics.json says so)";
  const bool refined = m.contains("ml") && m["ml"].contains("filter_position_rmse_per_run_m");
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  const std::string algorithm = m["algorithm"].get<std::string>();
  s << m["scenario"].get<std::string>() << " " << algorithm;
  if (algorithm != "mlslam" && algorithm != "dr") s << " N=" << m["particles"].get<int>();  // no particles
  s << " runs=" << m["runs"].get<int>() << " clutter=" << m["clutter_rate"].get<double>() << ": "
    << (refined ? "refined " : "") << "position RMSE " << m["position_rmse_m"].get<double>()
    << " m, heading RMSE " << m["heading_rmse_deg"].get<double>() << " deg";
  if (m.contains("ospa") && m["ospa"]["mean_over_steps_m"].is_number()) {
    // the per-step OSPA scores the filter's map at each step; the refinement has one map, at the end
    s << ", mean OSPA " << m["ospa"]["mean_over_steps_m"].get<double>() << " m"
      << (refined ? " (the filter's maps, step by step)" : "");
  } else if (m.contains("ospa")) {
    s << ", final-map OSPA " << m["ospa"]["final_m"]["mean"].get<double>() << " m";
  }
  if (m.contains("gospa")) s << ", GOSPA " << m["gospa"]["distance_m"]["mean"].get<double>() << " m";
  s << ", " << m["ms_per_step"]["mean"].get<double>() << " ms/step";
  if (m["ess_percent"].is_number()) {
    s << ", ESS " << m["ess_percent"].get<double>() << " %, resampling "
      << m["resampling_percent"].get<double>() << " %";
  }
  if (refined) {
    s << "; per run: refined position RMSE " << m["position_rmse_per_run_m"]["mean"].get<double>()
      << " m, the filter's " << m["ml"]["filter_position_rmse_per_run_m"]["mean"].get<double>() << " m";
    if (m["ml"].contains("filter_gospa_m"))
      s << ", GOSPA refined " << m["gospa"]["distance_m"]["mean"].get<double>() << " m, the filter's "
        << m["ml"]["filter_gospa_m"]["mean"].get<double>() << " m";
  }
  if (m.value("interrupted", false))
    s << " (interrupted: " << m["runs"].get<int>() << " of " << m["runs_requested"].get<int>() << " runs)";
  return s.str();
}

}  // namespace glmbslam::app
