// `glmbslam sim` keeps its work when stopped (SIGTERM/SIGINT: no new run starts, runs in progress stop at
// their next step, metrics.json covers the finished runs and says so) and honours a config file's particles
// and seed unless a flag names them.
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/glmbslam_process.hpp"
#include "app/sim_runner.hpp"
#include "core/interrupt.hpp"
#include "core/progress.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

SimOptions short_paper2019(const fs::path& out) {
  SimOptions o;
  o.scenario = "paper2019";
  o.algorithm = "glmb2";
  o.runs = 1;
  o.max_steps = 15;
  o.plots = false;
  o.out_dir = out.string();
  return o;
}

TEST(SimFlagsOverConfig, ConfigParticlesAndSeedHoldUnlessAFlagNamesThem) {
  ProgressReporter::set_enabled(false);
  const fs::path dir = test::fresh_temp_dir("sim_flags");
  const fs::path config = dir / "sim.yaml";
  std::ofstream(config) << "rbpf:\n  particles: 3\n  seed: 5\n";

  SimOptions from_file = short_paper2019(dir / "file");
  from_file.config_file = config.string();
  const nlohmann::json file = run_simulation(from_file);
  EXPECT_EQ(file.at("particles").get<int>(), 3);
  EXPECT_EQ(file.at("seed").get<int>(), 5);

  SimOptions flags = from_file;
  flags.out_dir = (dir / "flags").string();
  flags.particles = 2;
  flags.seed = 9;
  const nlohmann::json flagged = run_simulation(flags);
  EXPECT_EQ(flagged.at("particles").get<int>(), 2);
  EXPECT_EQ(flagged.at("seed").get<int>(), 9);

  SimOptions defaults = short_paper2019(dir / "defaults");
  const nlohmann::json builtin = run_simulation(defaults);
  EXPECT_EQ(builtin.at("particles").get<int>(), 10);
  EXPECT_EQ(builtin.at("seed").get<int>(), 0);
  fs::remove_all(dir);
}

TEST(SimInterrupt, AStopBeforeAnyRunFinishesWritesMetricsThatSaySo) {
  ProgressReporter::set_enabled(false);
  const fs::path dir = test::fresh_temp_dir("sim_interrupt_early");
  SimOptions o = short_paper2019(dir);
  o.runs = 3;
  request_interrupt(SIGTERM);
  const nlohmann::json m = run_simulation(o);
  clear_interrupt();
  set_graceful_interrupts(false);
  EXPECT_TRUE(m.at("interrupted").get<bool>());
  EXPECT_EQ(m.at("runs").get<int>(), 0);
  EXPECT_EQ(m.at("runs_requested").get<int>(), 3);
  std::ifstream in(dir / "metrics.json");
  ASSERT_TRUE(in) << "metrics.json written";
  EXPECT_EQ(nlohmann::json::parse(in).at("runs").get<int>(), 0);
  EXPECT_NE(summarize_simulation(m).find("interrupted"), std::string::npos);
  fs::remove_all(dir);
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(SimInterrupt, SigtermKeepsTheFinishedRunsAndExits143) {
  if (!fs::exists(test::glmbslam_binary())) GTEST_SKIP() << "glmbslam executable not built";
  const fs::path out = test::fresh_temp_dir("sim_interrupt");
  const fs::path log = out.string() + ".log";
  glmbslam::test::remove_after_test(log);
  fs::remove(log);            // a previous run's log would be read as this run's progress
  constexpr int kRuns = 200;  // far more than finish before the signal, even on a fast machine
  const pid_t pid = test::start_glmbslam(
      {"--threads", "1", "--log-level", "info", "sim", "--scenario", "paper2019", "--particles", "2",
       "--runs", std::to_string(kRuns), "--no-plots", "--out", out.string()},
      log);
  bool one_done = false;
  for (int i = 0; i < 60000 && !one_done; ++i) {  // 10 min at most (sanitizer builds, loaded machines)
    one_done = read_all(log).find("done (1/") != std::string::npos;
    if (!one_done) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(one_done) << "no run finished; log: " << read_all(log);
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  const int status = test::wait_for(pid);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143);

  std::ifstream in(out / "metrics.json");
  ASSERT_TRUE(in) << "metrics.json written";
  const nlohmann::json m = nlohmann::json::parse(in);
  EXPECT_TRUE(m.at("interrupted").get<bool>());
  const int runs = m.at("runs").get<int>();
  EXPECT_GE(runs, 1);
  EXPECT_LT(runs, kRuns);
  EXPECT_EQ(m.at("runs_requested").get<int>(), kRuns);
  // one thread: the runs finish in order, so the finished ones are 0 .. runs − 1
  const auto indices = m.at("run_indices").get<std::vector<int>>();
  ASSERT_EQ(indices.size(), static_cast<std::size_t>(runs));
  for (int i = 0; i < runs; ++i) EXPECT_EQ(indices[static_cast<std::size_t>(i)], i);
  EXPECT_EQ(m.at("position_rmse_each_run_m").size(), static_cast<std::size_t>(runs));
  EXPECT_GT(m.at("position_rmse_m").get<double>(), 0.0);
  fs::remove_all(out);
}

}  // namespace
}  // namespace glmbslam::app
