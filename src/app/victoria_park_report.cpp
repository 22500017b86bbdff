#include "app/victoria_park_report.hpp"

#include "eval/html_report.hpp"
#include "eval/report_figures.hpp"

namespace glmbslam::app {

void write_victoria_park_report(const std::string& path, const VictoriaParkReportInput& in,
                                const nlohmann::json& m) {
  namespace colours = eval::report_colours;
  using json = nlohmann::json;
  eval::HtmlReport report("glmbslam run: Victoria Park, " + m.value("algorithm", std::string()) +
                              ", N = " + std::to_string(m.value("particles", 0)),
                          std::to_string(in.x.size()) + " steps, seed " + std::to_string(m.value("seed", 0)));
  auto number = [](const json& v) { return v.is_number() ? eval::format_number(v.get<double>(), 4) : "–"; };
  const bool refined = in.refined_map != nullptr;
  std::vector<std::vector<std::string>> summary = {
      {refined ? "filter: position RMSE against GPS [m]" : "position RMSE against GPS [m]",
       number(m["position_rmse_m"])},
      {"GPS fixes compared", std::to_string(in.error_m->size())},
      {refined ? "filter: landmarks" : "landmarks", std::to_string(in.map->size())},
      {"time per step, mean [ms]", eval::format_number(m["ms_per_step"].value("mean", 0.0), 4)}};
  if (refined) {
    const json& r = m["refined"];
    summary.push_back({"refined (RFS-ML): position RMSE against GPS [m]", number(r["position_rmse_m"])});
    summary.push_back({"refined: landmarks", std::to_string(in.refined_map->size())});
    summary.push_back({"refined: solve [s]", number(r["solve_s"])});
  }
  report.add_table("Summary", {"metric", "value"}, summary);

  report.add_section("Path and map",
                     "Map landmarks coloured by existence probability (hover: index, existence).");
  eval::ReportSeries2D gps{"GPS", {}, {}, colours::kGroundTruth, true};
  for (const auto& f : *in.gps) gps.x.push_back(f.position.x()), gps.y.push_back(f.position.y());
  const eval::ReportSeries2D est{refined ? "filter" : "estimate", in.x, in.y, colours::kRed, false};
  if (refined) {
    const eval::ReportSeries2D ref{"refined (RFS-ML)", in.refined_x, in.refined_y, colours::kRefined, false};
    eval::add_plane_view(report, "Refined path and map over the GPS fixes", *in.refined_map, {gps, est, ref});
  } else {
    eval::add_plane_view(report, "Estimated path and map over the GPS fixes", *in.map, {gps, est});
  }

  report.add_section("Over time");
  json errors = json::array(
      {eval::line_trace(refined ? "filter" : "error", *in.error_time_s, *in.error_m, colours::kRed)});
  if (refined)
    errors.push_back(
        eval::line_trace("refined", *in.refined_error_time_s, *in.refined_error_m, colours::kRefined));
  report.add_plot("Position error against GPS", errors, eval::axes_layout("time [s]", "‖estimate − GPS‖ [m]"),
                  350);
  std::vector<double> ess;
  for (double e : *in.ess) ess.push_back(100.0 * e);
  const std::vector<double> steps = eval::index_axis(ess.size());
  report.add_plot("Effective sample size (before resampling)",
                  json::array({eval::line_trace("ESS / N", steps, ess, colours::kSlam)}),
                  eval::axes_layout("step", "ESS [% of N]"), 320);
  report.add_plot("Time per step", json::array({eval::line_trace("ms", steps, *in.ms, colours::kPurple)}),
                  eval::axes_layout("step", "time [ms]"), 320);
  report.add_section("Metrics", "metrics.json, flattened.");
  report.add_table("", {"key", "value"}, eval::metrics_rows(m));
  report.write(path);
}

}  // namespace glmbslam::app
