// Timing of the RFS-ML solver (backend/mlslam, paper 004) on the phdslam3 benchmark (realisation 0 of
// ../shared/data/phdslam3_synthetic, the first 500 / 1000 / 4000 steps, models as `glmbslam sim` builds
// them): the log-likelihood l of Eq. 8 (one E-step over every scan: gating, ranked assignments, marginals) at
// the true trajectory and map, and a whole refinement solve from the truth with the phdslam3 settings
// (config/sim_phdslam3.yaml: undamped M-steps; cardinality moves on). Skips, with a message, without the
// data.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>

#include <benchmark/benchmark.h>

#include "app/sim_models.hpp"
#include "backend/mlslam/rfs_ml_slam.hpp"
#include "sim/scenario_phdslam3.hpp"

namespace {

using glmbslam::backend::RangeBearingModel;
using glmbslam::backend::UnicycleMotion;
using Slam = glmbslam::backend::RfsMlSlam<UnicycleMotion, RangeBearingModel>;

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("GLMBSLAM_DATA"); env != nullptr && *env != '\0') return env;
  return GLMBSLAM_DEFAULT_DATA_DIR;
}

/// One realisation cut to `steps`, with the solver's inputs and the truth as the start.
struct Problem {
  glmbslam::sim::Scenario2D scenario;
  Slam::ControlList controls;
  std::vector<Slam::MeasurementSet> scans;
  Slam::PoseList truth;
  Slam::LandmarkList landmarks;
};

const Problem* problem(std::size_t steps) {
  static std::map<std::size_t, std::unique_ptr<Problem>> cache;
  auto& slot = cache[steps];
  if (slot) return slot.get();
  const auto file = glmbslam::sim::phdslam3_environment_path(data_dir());
  if (!std::filesystem::exists(file)) return nullptr;
  static const auto env = glmbslam::sim::load_phdslam3_environment(file);
  glmbslam::sim::PhdSlam3Options options;
  options.max_steps = steps;
  slot = std::make_unique<Problem>();
  Problem& p = *slot;
  p.scenario = glmbslam::sim::make_phdslam3_scenario(env, 0, options);
  for (const auto& u : p.scenario.controls) p.controls.push_back(u);
  for (const auto& z : p.scenario.measurements) p.scans.emplace_back(z.begin(), z.end());
  p.truth.assign(p.scenario.poses.begin(), p.scenario.poses.end());
  p.landmarks.assign(p.scenario.landmarks.begin(), p.scenario.landmarks.end());
  return slot.get();
}

/// The problem of state.range(0) steps, or null with the benchmark marked skipped.
const Problem* problem_or_skip(benchmark::State& state) {
  const Problem* p = problem(static_cast<std::size_t>(state.range(0)));
  if (p == nullptr) state.SkipWithError("phdslam3_synthetic not found (set GLMBSLAM_DATA)");
  return p;
}

/// The solver with the models and settings of `glmbslam sim --scenario phdslam3 --refine ml`.
Slam solver_for(const Problem& p) {
  glmbslam::backend::MlSlamConfig c;
  c.initial_trust_region_radius = 1e8;  // config/sim_phdslam3.yaml
  return Slam(UnicycleMotion(glmbslam::app::sim_unicycle_config(p.scenario)),
              glmbslam::app::sim_measurement_model(p.scenario), c);
}

void BM_MlSlamLogLikelihoodPhdslam3(benchmark::State& state) {
  const Problem* p = problem_or_skip(state);
  if (p == nullptr) return;
  const Slam slam = solver_for(*p);
  double l = 0.0;
  for (auto _ : state) {
    l = slam.log_likelihood(p->truth, p->controls, p->scans, p->landmarks);
    benchmark::DoNotOptimize(l);
  }
  state.counters["scans_per_s"] =
      benchmark::Counter(static_cast<double>(p->scans.size()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["log_likelihood"] = l;
}
BENCHMARK(BM_MlSlamLogLikelihoodPhdslam3)->Arg(500)->Arg(4000)->Unit(benchmark::kMillisecond);

void BM_MlSlamSolvePhdslam3(benchmark::State& state) {
  const Problem* p = problem_or_skip(state);
  if (p == nullptr) return;
  const Slam slam = solver_for(*p);
  glmbslam::backend::MlSlamReport report;
  for (auto _ : state) {
    Slam::PoseList x = p->truth;
    Slam::LandmarkList m = p->landmarks;
    report = slam.solve(x, p->controls, p->scans, m);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["rounds"] = report.rounds;
  state.counters["e_step_ms"] = report.e_step_ms;
  state.counters["m_step_ms"] = report.m_step_ms;
  state.counters["moves_ms"] = report.moves_ms;
}
BENCHMARK(BM_MlSlamSolvePhdslam3)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
