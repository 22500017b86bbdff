// Bad input end to end through the glmbslam executable (docs/robustness.md): empty and featureless frames, a
// sequence without ground truth, an output folder that cannot be created, and an output folder that fills up.
// Each either runs with one pose per frame or ends with a one-line error (exit 2) and no file that looks
// complete but is not.
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "app/glmbslam_process.hpp"
#include "core/progress.hpp"
#include "io/trajectory_io.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 12;

class BadInputRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::glmbslam_binary())) GTEST_SKIP() << "glmbslam executable not built";
    dir_ = test::fresh_temp_dir("bad_input");
    ProgressReporter::set_enabled(false);
    sim::SequenceRenderOptions o;
    o.out_dir = (dir_ / "clip").string();
    o.frames = "0:" + std::to_string(kFrames);
    sim::render_kitti_sequence(o);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path sequence() const { return dir_ / "clip" / "sequences" / "00"; }
  int run(const fs::path& out, rlim_t max_file_bytes = 0) const {
    return test::run_glmbslam({"--threads", "1", "--log-level", "warn", "run", sequence().string(), "--out",
                               out.string(), "--particles", "2"},
                              dir_ / "run.log", max_file_bytes);
  }
  std::string log() const {
    std::ifstream in(dir_ / "run.log");
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  static nlohmann::json metrics(const fs::path& out) {
    std::ifstream in(out / "metrics.json");
    return nlohmann::json::parse(in);
  }
  fs::path dir_;
};

TEST_F(BadInputRun, EmptyImageFileAndFeaturelessFrameKeepOnePosePerFrame) {
  const fs::path seq = sequence();
  std::ofstream(seq / "image_0" / "000004.png", std::ios::trunc);  // empty file (0 bytes)
  const cv::Mat probe = cv::imread((seq / "image_0" / "000000.png").string(), cv::IMREAD_GRAYSCALE);
  const cv::Mat black = cv::Mat::zeros(probe.size(), CV_8U);  // decodes fine, no feature at all
  cv::imwrite((seq / "image_0" / "000008.png").string(), black);
  cv::imwrite((seq / "image_1" / "000008.png").string(), black);
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run(out), 0) << log();
  EXPECT_EQ(io::read_kitti_poses((out / "trajectory.txt").string()).size(),
            static_cast<std::size_t>(kFrames));
  const nlohmann::json m = metrics(out);
  EXPECT_EQ(m["filter"]["missing_frames"].get<int>(), 1);
  // The featureless frame falls back to constant velocity (the unreadable one is counted in missing_frames).
  EXPECT_GE(m["filter"]["vo_fallback_frames"].get<int>(), 1);
  EXPECT_FALSE(m["interrupted"].get<bool>());
}

TEST_F(BadInputRun, MissingGroundTruthRunsWithoutEvaluation) {
  fs::remove_all(dir_ / "clip" / "poses");
  const fs::path out = dir_ / "out";
  ASSERT_EQ(run(out), 0) << log();
  EXPECT_EQ(io::read_kitti_poses((out / "trajectory.txt").string()).size(),
            static_cast<std::size_t>(kFrames));
  const nlohmann::json m = metrics(out);
  EXPECT_FALSE(m.contains("slam"));
  EXPECT_FALSE(m.contains("vo"));
  EXPECT_FALSE(fs::exists(out / "ground_truth.txt"));
}

TEST_F(BadInputRun, OutputFolderThatCannotBeCreatedIsAOneLineError) {
  std::ofstream(dir_ / "a_file") << "x";
  EXPECT_EQ(run(dir_ / "a_file" / "out"), 2);
  EXPECT_NE(log().find("a_file"), std::string::npos) << log();
}

TEST_F(BadInputRun, ZeroParticlesAndANegativeSeedAreErrorsNotTheDefaults) {
  // both used to fall back silently to the config's values
  for (const auto& [flag, value, message] : {std::tuple<std::string, std::string, std::string>{
                                                 "--particles", "0", "--particles must be at least 1"},
                                             {"--seed", "-1", "--seed must not be negative"}}) {
    EXPECT_EQ(test::run_glmbslam({"--log-level", "warn", "run", sequence().string(), "--out",
                                  (dir_ / "o").string(), flag, value},
                                 dir_ / "run.log"),
              2);
    EXPECT_NE(log().find(message), std::string::npos) << log();
    EXPECT_FALSE(fs::exists(dir_ / "o" / "metrics.json"));
  }
}

TEST_F(BadInputRun, OutputFolderThatFillsUpIsAOneLineErrorAndLeavesNoFalseFile) {
  // Every file may grow to 64 KiB only: the trajectories fit, the larger outputs (plots, report.html) do not.
  const fs::path out = dir_ / "out";
  EXPECT_EQ(run(out, 64 * 1024), 2) << log();
  const std::string text = log();
  const std::size_t failed = text.find(": write failed");
  ASSERT_NE(failed, std::string::npos) << text;
  const std::size_t start = text.rfind(out.string(), failed);
  ASSERT_NE(start, std::string::npos) << "the error names the file: " << text;
  const fs::path file = text.substr(start, failed - start);
  EXPECT_FALSE(fs::exists(file)) << file << " must not be left under its final name";
  for (const auto& entry : fs::recursive_directory_iterator(out)) {  // no temporary left behind
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

}  // namespace
}  // namespace glmbslam::app
