#pragma once
// The files `glmbslam sim` writes into --out: the PNG plots (unless --no-plots), metrics.json (atomically)
// and report.html (app/sim_report.hpp); plots and report show the first finished run.
#include "app/sim_metrics.hpp"
#include "app/sim_run_record.hpp"
#include "app/sim_runner.hpp"
#include "sim/scenario2d.hpp"

namespace glmbslam::app {

/// `first` is the record of the first finished run, `truth` its scenario.
void write_sim_outputs(const SimOptions& o, const SimMetrics& metrics, const sim::Scenario2D& truth,
                       const SimRunRecord& first);

}  // namespace glmbslam::app
