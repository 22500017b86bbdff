#pragma once
// The Monte Carlo runs of `glmbslam sim`, in parallel over runs (core/parallel.hpp). On SIGINT/SIGTERM no
// new run starts and the runs in progress stop at their next step; the finished ones are kept.
#include <cstddef>
#include <vector>

#include "app/sim_filters.hpp"
#include "app/sim_run_record.hpp"
#include "app/sim_runner.hpp"
#include "app/sim_scenarios.hpp"

namespace glmbslam::app {

struct SimRuns {
  std::vector<SimRunRecord> records;  ///< the finished runs, in run order
  std::vector<int> run_indices;       ///< entry i: the run (data realisation) of records[i]
  std::size_t requested = 0;          ///< o.runs
  double wall_s = 0.0;                ///< wall time of the runs
  bool interrupted() const { return records.size() < requested; }
};

/// Runs o.first_run .. o.first_run + o.runs − 1; rethrows the first failed run's error (in run order) once
/// all have ended.
SimRuns run_monte_carlo(const SimOptions& o, const SimFilters& f, const SimScenarios& scenarios);

}  // namespace glmbslam::app
