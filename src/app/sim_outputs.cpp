#include "app/sim_outputs.hpp"

#include <filesystem>
#include <string>
#include <vector>

#include "app/sim_report.hpp"
#include "eval/line_plot.hpp"
#include "eval/report.hpp"

namespace glmbslam::app {

namespace {

/// trajectory_map.png (run o.first_run), rmse_xy.png, rmse_heading.png and, for paper2019, ospa.png.
void write_plots(const std::filesystem::path& dir, const sim::Scenario2D& s0, const SimRunRecord& r0,
                 const SimStepCurves& curves, const SimOptions& o) {
  const std::string tag = o.scenario + " " + o.algorithm + " N=" + std::to_string(*o.particles);
  {
    eval::LinePlot plot("Trajectory and map, run " + std::to_string(o.first_run) + " (" + tag + ")", "x [m]",
                        "y [m]");
    std::vector<double> gx, gy, ex, ey, lx, ly, mx, my;
    for (const auto& p : s0.poses) gx.push_back(p(0)), gy.push_back(p(1));
    for (const auto& p : r0.estimates) ex.push_back(p(0)), ey.push_back(p(1));
    for (const auto& l : s0.landmarks) lx.push_back(l(0)), ly.push_back(l(1));
    for (const auto& m : r0.final_map) mx.push_back(m(0)), my.push_back(m(1));
    // drawn widest first, so the paths on top of each other stay visible
    plot.add_series(gx, gy, eval::colours::kBlue, "ground truth", eval::SeriesStyle::kLine, 6);
    if (!r0.filter_estimates.empty()) {
      std::vector<double> fx, fy;
      for (const auto& p : r0.filter_estimates) fx.push_back(p(0)), fy.push_back(p(1));
      plot.add_series(fx, fy, eval::colours::kOrange, "filter", eval::SeriesStyle::kLine, 4);
    }
    plot.add_series(ex, ey, eval::colours::kRed,
                    r0.filter_estimates.empty() ? "estimate" : "refined (RFS-ML)");
    plot.add_series(lx, ly, eval::colours::kBlack, "landmarks", eval::SeriesStyle::kMarkers);
    plot.add_series(mx, my, eval::colours::kRed, "map estimate", eval::SeriesStyle::kMarkers);
    plot.set_equal_aspect(true);
    plot.save_png((dir / "trajectory_map.png").string());
  }
  std::vector<double> steps(curves.rmse_x.size());
  for (std::size_t k = 0; k < steps.size(); ++k) steps[k] = static_cast<double>(k);
  {
    eval::LinePlot plot("Position RMSE over the runs (" + tag + ")", "time step", "RMSE [m]");
    plot.add_series(steps, curves.rmse_x, eval::colours::kBlue, "X");
    plot.add_series(steps, curves.rmse_y, eval::colours::kOrange, "Y");
    plot.set_include_zero_y(true);
    plot.save_png((dir / "rmse_xy.png").string());
  }
  {
    eval::LinePlot plot("Heading RMSE over the runs (" + tag + ")", "time step", "RMSE [deg]");
    plot.add_series(steps, curves.rmse_h, eval::colours::kGreen, "heading");
    plot.set_include_zero_y(true);
    plot.save_png((dir / "rmse_heading.png").string());
  }
  if (!curves.ospa_mean.empty()) {
    std::vector<double> k1(curves.ospa_mean.size());
    for (std::size_t k = 0; k < k1.size(); ++k) k1[k] = static_cast<double>(k + 1);
    eval::LinePlot plot("Mean map OSPA (c = 0.5 m, p = 1) (" + tag + ")", "time step", "OSPA [m]");
    plot.add_series(k1, curves.ospa_mean, eval::colours::kPurple, "OSPA");
    plot.set_include_zero_y(true);
    plot.save_png((dir / "ospa.png").string());
  }
}

}  // namespace

void write_sim_outputs(const SimOptions& o, const SimMetrics& metrics, const sim::Scenario2D& truth,
                       const SimRunRecord& first) {
  const std::filesystem::path dir(o.out_dir);
  if (o.plots) write_plots(dir, truth, first, metrics.curves, o);
  eval::write_json_file((dir / "metrics.json").string(), metrics.json);
  write_sim_report((dir / "report.html").string(), metrics.json, truth, first.estimates, first.final_map,
                   first.filter_estimates);
}

}  // namespace glmbslam::app
