#pragma once
// The 2D scenarios of `glmbslam sim`, run by run: paper2019 (one data realisation for every run, cut to
// --max-steps), paper004 and phdslam3 (regenerated per run, the run index being the data seed).
#include <cstddef>
#include <string>

#include "app/sim_runner.hpp"
#include "sim/scenario2d.hpp"
#include "sim/scenario_phdslam3.hpp"

namespace glmbslam::app {

class SimScenarios {
 public:
  /// For o.scenario = paper2019, paper004 or phdslam3 (whose environment is read from the data root: --data,
  /// $GLMBSLAM_DATA or ../shared/data; InputError if unreadable).
  explicit SimScenarios(const SimOptions& o);

  /// The scenario of run `run` (the data realisation).
  sim::Scenario2D of_run(int run) const;

  /// λ_c per scan, as metrics.json reports it.
  double clutter_rate() const { return clutter_rate_; }

 private:
  std::string name_;
  double clutter_option_;  ///< --clutter (< 0: the scenario's default)
  std::size_t max_steps_;  ///< --max-steps (0: all)
  double clutter_rate_ = 0.0;
  sim::Scenario2D paper2019_;
  sim::PhdSlam3Environment phdslam3_;
};

}  // namespace glmbslam::app
