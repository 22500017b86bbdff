#include "app/sim_report.hpp"

#include <limits>

#include "eval/html_report.hpp"
#include "eval/report_figures.hpp"

namespace glmbslam::app {
namespace {

namespace colours = eval::report_colours;
using json = nlohmann::json;

std::vector<double> numbers(const json& j) {
  std::vector<double> v;
  for (const auto& x : j)
    v.push_back(x.is_number() ? x.get<double>() : std::numeric_limits<double>::quiet_NaN());
  return v;
}

std::string summary_cell(const json& s) {
  return eval::format_number(s.value("mean", 0.0), 4) + " ± " + eval::format_number(s.value("std", 0.0), 3);
}

}  // namespace

void write_sim_report(const std::string& path, const json& m, const sim::Scenario2D& scenario,
                      const std::vector<Eigen::Vector3d>& estimates, const std::vector<Eigen::Vector2d>& map,
                      const std::vector<Eigen::Vector3d>& filter_estimates) {
  const int first_run = m.value("first_run", 0);
  const int runs = m.value("runs", 1);
  eval::HtmlReport report("glmbslam sim: " + m.value("scenario", std::string()) + ", " +
                              m.value("algorithm", std::string()) +
                              ", N = " + std::to_string(m.value("particles", 0)),
                          std::to_string(runs) + " Monte Carlo run(s) from run " + std::to_string(first_run) +
                              ", clutter rate " + eval::format_number(m.value("clutter_rate", 0.0), 4) +
                              ", " + std::to_string(m.value("steps", 0)) + " steps");

  std::vector<std::vector<std::string>> headline = {
      {"position RMSE per run [m]", summary_cell(m["position_rmse_per_run_m"])},
      {"position RMSE pooled over the runs [m]", eval::format_number(m.value("position_rmse_m", 0.0), 4)},
      {"heading RMSE per run [deg]", summary_cell(m["heading_rmse_per_run_deg"])},
      {"time per step [ms]", summary_cell(m["ms_per_step"])}};
  if (m.contains("gospa"))
    headline.push_back({"final map GOSPA [m]", summary_cell(m["gospa"]["distance_m"])});
  if (m.contains("ospa") && m["ospa"]["mean_over_steps_m"].is_number())
    headline.push_back({"map OSPA, mean over steps [m]",
                        eval::format_number(m["ospa"]["mean_over_steps_m"].get<double>(), 4)});
  else if (m.contains("ospa"))  // RFS-ML from the odometry: one map, at the end
    headline.push_back({"final map OSPA [m]", summary_cell(m["ospa"]["final_m"])});
  if (m.contains("ml") && m["ml"].contains("filter_position_rmse_per_run_m")) {
    headline.push_back({"filter before the refinement: position RMSE per run [m]",
                        summary_cell(m["ml"]["filter_position_rmse_per_run_m"])});
    if (m["ml"].contains("filter_gospa_m"))
      headline.push_back(
          {"filter before the refinement: final map GOSPA [m]", summary_cell(m["ml"]["filter_gospa_m"])});
  }
  report.add_table("Summary (mean ± standard deviation over the runs)", {"metric", "value"}, headline);

  // Per-run table.
  const std::vector<double> rmse = numbers(m.value("position_rmse_each_run_m", json::array()));
  const std::vector<double> gospa = m.contains("gospa")
                                        ? numbers(m["gospa"].value("distance_each_run_m", json::array()))
                                        : std::vector<double>();
  const json ml = m.value("ml", json::object());
  const std::vector<double> filter_rmse = numbers(ml.value("filter_position_rmse_each_run_m", json::array()));
  const std::vector<double> filter_gospa = numbers(ml.value("filter_gospa_each_run_m", json::array()));
  const bool refined = !filter_rmse.empty();
  auto cell = [](const std::vector<double>& v, std::size_t i) {
    return i < v.size() ? eval::format_number(v[i], 4) : std::string("–");
  };
  std::vector<std::vector<std::string>> per_run;
  for (std::size_t i = 0; i < rmse.size(); ++i) {
    std::vector<std::string> row = {std::to_string(first_run + static_cast<int>(i)), cell(rmse, i),
                                    cell(gospa, i)};
    if (refined) row.push_back(cell(filter_rmse, i)), row.push_back(cell(filter_gospa, i));
    per_run.push_back(row);
  }
  report.add_section("Per run");
  std::vector<std::string> columns = {"run", "position RMSE [m]", "GOSPA [m]"};
  if (refined) {
    columns = {"run", "refined position RMSE [m]", "refined GOSPA [m]", "filter position RMSE [m]",
               "filter GOSPA [m]"};
  }
  report.add_table("Position RMSE and final-map GOSPA of each run (run index = data realisation)", columns,
                   per_run);
  const std::vector<double> run_axis = eval::index_axis(rmse.size(), static_cast<double>(first_run));
  json per_run_traces = json::array({eval::line_trace("position RMSE [m]", run_axis, rmse, colours::kSlam)});
  if (!gospa.empty())
    per_run_traces.push_back(eval::line_trace("GOSPA [m]", run_axis, gospa, colours::kPurple));
  for (auto& t : per_run_traces) t["mode"] = "markers";
  report.add_plot("Per-run errors", per_run_traces, eval::axes_layout("run", "error [m]"), 350);

  report.add_section("Trajectory and map of run " + std::to_string(first_run));
  eval::ReportSeries2D gt{"ground truth", {}, {}, colours::kGroundTruth, false};
  for (const auto& p : scenario.poses) gt.x.push_back(p(0)), gt.y.push_back(p(1));
  eval::ReportSeries2D est{
      refined ? "refined (RFS-ML)" : "estimate", {}, {}, refined ? colours::kRefined : colours::kSlam, false};
  for (const auto& p : estimates) est.x.push_back(p(0)), est.y.push_back(p(1));
  eval::ReportSeries2D filter{"filter", {}, {}, colours::kSlam, false};
  for (const auto& p : filter_estimates) filter.x.push_back(p(0)), filter.y.push_back(p(1));
  eval::ReportSeries2D lm{"true landmarks", {}, {}, colours::kGroundTruth, true};
  for (const auto& l : scenario.landmarks) lm.x.push_back(l(0)), lm.y.push_back(l(1));
  eval::ReportSeries2D mp{"map estimate", {}, {}, colours::kRed, true};
  for (const auto& l : map) mp.x.push_back(l(0)), mp.y.push_back(l(1));
  std::vector<eval::ReportSeries2D> top = {lm, gt};
  if (!filter_estimates.empty()) top.push_back(filter);
  top.push_back(est);
  top.push_back(mp);
  eval::add_plane_view(report, "Trajectory and map (top view)", {}, top);

  report.add_section("Over time", "RMSE over the runs at each step.");
  const json& per_step = m["rmse_per_step"];
  const std::vector<double> x_rmse = numbers(per_step["x_m"]), y_rmse = numbers(per_step["y_m"]);
  const std::vector<double> steps = eval::index_axis(x_rmse.size());
  report.add_plot("Position RMSE",
                  json::array({eval::line_trace("x", steps, x_rmse, colours::kSlam),
                               eval::line_trace("y", steps, y_rmse, colours::kVo)}),
                  eval::axes_layout("time step", "RMSE [m]"), 350);
  report.add_plot(
      "Heading RMSE",
      json::array({eval::line_trace("heading", steps, numbers(per_step["heading_deg"]), colours::kRefined)}),
      eval::axes_layout("time step", "RMSE [deg]"), 350);
  if (m.contains("ospa") && m["ospa"].contains("per_step_mean_m")) {
    const std::vector<double> ospa = numbers(m["ospa"]["per_step_mean_m"]);
    report.add_plot(
        "Map OSPA, mean over the runs (c = 0.5 m, p = 1)",
        json::array({eval::line_trace("OSPA", eval::index_axis(ospa.size(), 1.0), ospa, colours::kPurple)}),
        eval::axes_layout("time step", "OSPA [m]"), 350);
  }
  report.add_section("Metrics", "metrics.json, flattened.");
  report.add_table("", {"key", "value"}, eval::metrics_rows(m));
  report.write(path);
}

}  // namespace glmbslam::app
