// Command-line flags override config files for every key they name: `glmbslam [--threads N] run ...
// --particles
// --seed --algorithm` against a config that sets threads / rbpf.particles / rbpf.seed / the algorithm to
// other values, for the stereo pipeline and Victoria Park; without the flags the config's values hold.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/progress.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

/// Runs the glmbslam executable with `args`; returns the exit status and the output folder's metrics.json.
nlohmann::json metrics_of_run(const std::string& args, const fs::path& out) {
  const std::string command = glmbslam::test::glmbslam_binary().string() + " --log-level error " + args +
                              " --out " + out.string() + " > " + (out.string() + ".log") + " 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << command;
  std::ifstream in(out / "metrics.json");
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

/// The run settings metrics.json reports.
void expect_settings(const nlohmann::json& m, int particles, int seed, const std::string& algorithm) {
  EXPECT_EQ(m.value("particles", -1), particles);
  EXPECT_EQ(m.value("seed", -1), seed);
  EXPECT_EQ(m.value("algorithm", ""), algorithm);
}

fs::path write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

TEST(FlagsOverConfig, VictoriaParkThreadsParticlesSeedAndAlgorithm) {
  GLMBSLAM_REQUIRE_DATA(data, "victoria_park");
  const fs::path dir = glmbslam::test::fresh_temp_dir("flags");
  const fs::path config =
      write_file(dir / "vp.yaml", "algorithm: glmb1\nthreads: 1\nrbpf:\n  particles: 3\n  seed: 5\n");
  const std::string common = " run " + data.string() + " --frames 0:30 --config " + config.string();
  const nlohmann::json flags =
      metrics_of_run("--threads 2" + common + " --particles 2 --seed 9 --algorithm glmb2", dir / "flags");
  EXPECT_EQ(flags.value("threads", -1), 2);
  expect_settings(flags, 2, 9, "glmb2");
  const nlohmann::json file = metrics_of_run(common, dir / "file");
  EXPECT_EQ(file.value("threads", -1), 1);
  expect_settings(file, 3, 5, "glmb1");
  fs::remove_all(dir);
}

TEST(FlagsOverConfig, StereoParticlesSeedAndAlgorithm) {
  const fs::path dir = glmbslam::test::fresh_temp_dir("flags");
  ProgressReporter::set_enabled(false);
  sim::SequenceRenderOptions render;
  render.out_dir = (dir / "clip").string();
  render.frames = "0:4";
  sim::render_kitti_sequence(render);
  const fs::path config =
      write_file(dir / "stereo.yaml",
                 "rbpf:\n  particles: 3\n  seed: 5\npipeline:\n  algorithm: glmb1\n  write_plots: false\n");
  const std::string common =
      " run " + (dir / "clip" / "sequences" / "00").string() + " --config " + config.string();
  const nlohmann::json flags =
      metrics_of_run(common + " --particles 2 --seed 9 --algorithm glmb2", dir / "flags");
  expect_settings(flags, 2, 9, "glmb2");
  const nlohmann::json file = metrics_of_run(common, dir / "file");
  expect_settings(file, 3, 5, "glmb1");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace glmbslam::app
