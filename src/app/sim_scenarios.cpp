#include "app/sim_scenarios.hpp"

#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "sim/scenario_paper004.hpp"
#include "sim/scenario_paper2019.hpp"

namespace glmbslam::app {

namespace {

std::filesystem::path resolve_data_dir(const SimOptions& o) {
  if (!o.data_dir.empty()) return o.data_dir;
  if (const char* env = std::getenv("GLMBSLAM_DATA"); env != nullptr && *env != '\0') return env;
  return "../shared/data";
}

/// Only the first `steps` steps of `s`.
void truncate(sim::Scenario2D& s, std::size_t steps) {
  s.poses.resize(steps);
  s.true_controls.resize(steps);
  s.controls.resize(steps);
  s.measurements.resize(steps);
  s.measurement_sources.resize(steps);
}

}  // namespace

SimScenarios::SimScenarios(const SimOptions& o)
    : name_(o.scenario), clutter_option_(o.clutter), max_steps_(o.max_steps) {
  if (name_ == "phdslam3") {
    phdslam3_ = sim::load_phdslam3_environment(sim::phdslam3_environment_path(resolve_data_dir(o)));
    clutter_rate_ = 5.0;
  } else if (name_ == "paper004") {
    clutter_rate_ = sim::make_paper004_scenario({clutter_option_, 0}).sensor.clutter_rate;
  } else {
    sim::Paper2019Options po;
    if (clutter_option_ >= 0.0) po.clutter_rate = clutter_option_;
    paper2019_ = sim::make_paper2019_scenario(po);
    if (max_steps_ > 0 && max_steps_ < paper2019_.steps()) truncate(paper2019_, max_steps_);
    clutter_rate_ = po.clutter_rate;
  }
}

sim::Scenario2D SimScenarios::of_run(int run) const {
  if (name_ == "paper2019") return paper2019_;
  if (name_ == "paper004")
    return sim::make_paper004_scenario({clutter_option_, static_cast<std::uint64_t>(run)});
  sim::PhdSlam3Options opt;
  opt.max_steps = max_steps_;
  return sim::make_phdslam3_scenario(phdslam3_, static_cast<std::uint64_t>(run), opt);
}

}  // namespace glmbslam::app
