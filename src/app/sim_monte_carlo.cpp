#include "app/sim_monte_carlo.hpp"

#include <exception>
#include <mutex>
#include <utility>

#include <spdlog/spdlog.h>

#include "app/sim_filter_run.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::app {

SimRuns run_monte_carlo(const SimOptions& o, const SimFilters& f, const SimScenarios& scenarios) {
  const std::size_t requested = static_cast<std::size_t>(o.runs);
  std::vector<SimRunRecord> records(requested);
  std::vector<std::exception_ptr> errors(requested);
  std::vector<char> finished(requested, 0);
  std::mutex log_mutex;
  std::size_t done = 0;
  Stopwatch wall;
  set_graceful_interrupts(
      true);  // SIGINT/SIGTERM: no new run starts, runs in progress stop at their next step
  parallel_for(requested, [&](std::size_t r) {
    if (interrupt_requested()) return;
    try {
      const int run = o.first_run + static_cast<int>(r);
      const sim::Scenario2D s = scenarios.of_run(run);
      records[r] = run_sim_filter(s, o, f, run);
      std::lock_guard<std::mutex> lock(log_mutex);
      finished[r] = 1;
      ++done;
      spdlog::info("sim {} {} N={}: run {} done ({}/{})", o.scenario, o.algorithm, *o.particles,
                   o.first_run + static_cast<int>(r), done, requested);
    } catch (const SimRunInterrupted&) {
      // left out: the metrics average finished runs only
    } catch (...) {
      errors[r] = std::current_exception();
    }
  });
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  SimRuns runs;
  runs.requested = requested;
  runs.wall_s = wall.elapsed_ms() / 1000.0;
  for (std::size_t r = 0; r < requested; ++r) {
    if (finished[r] == 0) continue;
    runs.run_indices.push_back(o.first_run + static_cast<int>(r));
    runs.records.push_back(std::move(records[r]));
  }
  if (runs.interrupted()) {
    spdlog::warn("sim: interrupted; {} of {} runs finished, the metrics cover those", runs.records.size(),
                 requested);
  }
  return runs;
}

}  // namespace glmbslam::app
