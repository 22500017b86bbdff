#pragma once
// report.html of `glmbslam sim` (eval/html_report.hpp): the first run's trajectory and map against the ground
// truth, position / heading RMSE and map OSPA over time, per-run RMSE and GOSPA tables, all metrics.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "sim/scenario2d.hpp"

namespace glmbslam::app {

/// `metrics` is the metrics.json of run_simulation; `estimates` (x, y, θ per step) and `map` are those of
/// the first run, on `scenario` (its ground truth); with --refine ml `filter_estimates` are the filter's
/// (drawn beside the refined path; empty otherwise) and the per-run table gives the filter's errors too.
void write_sim_report(const std::string& path, const nlohmann::json& metrics, const sim::Scenario2D& scenario,
                      const std::vector<Eigen::Vector3d>& estimates, const std::vector<Eigen::Vector2d>& map,
                      const std::vector<Eigen::Vector3d>& filter_estimates = {});

}  // namespace glmbslam::app
