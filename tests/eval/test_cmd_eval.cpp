// End-to-end checks of `glmbslam eval` (skipped when the executable has not been built).
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/trajectory_io.hpp"
#include "support/test_data.hpp"

namespace glmbslam::eval {
namespace {

#define REQUIRE_BINARY()                                                                   \
  if (!std::filesystem::exists(test::glmbslam_binary())) {                                 \
    GTEST_SKIP() << "glmbslam executable not built: " << test::glmbslam_binary().string(); \
  }

int run(const std::string& args, const std::filesystem::path& log) {
  const std::string cmd = test::glmbslam_binary().string() + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

PoseList line(int frames, double step) {
  PoseList poses;
  for (int i = 0; i < frames; ++i) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(0.0, 0.0, step * i);
    poses.push_back(T);
  }
  return poses;
}

TEST(CmdEval, MismatchedCountsGiveAOneLineError) {
  REQUIRE_BINARY();
  const auto dir = test::fresh_temp_dir("cmd_eval");
  io::write_kitti_poses((dir / "gt.txt").string(), line(20, 1.0));
  io::write_kitti_poses((dir / "est.txt").string(), line(19, 1.0));
  const int code = run("eval --gt " + (dir / "gt.txt").string() + " --est " + (dir / "est.txt").string() +
                           " --json " + (dir / "m.json").string(),
                       dir / "log.txt");
  EXPECT_EQ(code, 2);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("est.txt"), std::string::npos) << log;
  EXPECT_NE(log.find("19 poses"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.json"));
}

TEST(CmdEval, WritesJsonAndPlots) {
  REQUIRE_BINARY();
  const auto dir = test::fresh_temp_dir("cmd_eval");
  io::write_kitti_poses((dir / "gt.txt").string(), line(201, 1.0));
  io::write_kitti_poses((dir / "est.txt").string(), line(201, 1.01));
  const int code = run("eval --gt " + (dir / "gt.txt").string() + " --est " + (dir / "est.txt").string() +
                           " --json " + (dir / "m.json").string() + " --plot " + (dir / "plots").string(),
                       dir / "log.txt");
  ASSERT_EQ(code, 0) << slurp(dir / "log.txt");
  std::ifstream in(dir / "m.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_NEAR(j.at("kitti").at("t_rel_percent").get<double>(), 1.01, 1e-4);
  EXPECT_TRUE(std::filesystem::exists(dir / "plots" / "trajectory_top.png"));
  EXPECT_NE(slurp(dir / "log.txt").find("t_rel"), std::string::npos);
}

TEST(CmdEval, TumAssociatesByTimestamp) {
  REQUIRE_BINARY();
  const auto dir = test::fresh_temp_dir("cmd_eval");
  const PoseList gt = line(50, 1.0);
  std::vector<double> t_gt, t_est;
  for (int i = 0; i < 50; ++i) {
    t_gt.push_back(0.1 * i);
    t_est.push_back(0.1 * i + 0.003);
  }
  io::write_tum_trajectory((dir / "gt.tum").string(), gt, t_gt);
  io::write_tum_trajectory((dir / "est.tum").string(), line(50, 1.1), t_est);
  const int code = run("eval --format tum --gt " + (dir / "gt.tum").string() + " --est " +
                           (dir / "est.tum").string() + " --json " + (dir / "m.json").string(),
                       dir / "log.txt");
  ASSERT_EQ(code, 0) << slurp(dir / "log.txt");
  std::ifstream in(dir / "m.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("frames").get<int>(), 50);
  EXPECT_NEAR(j.at("rpe").at("trans_rmse_m").get<double>(), 0.1, 1e-6);
}

}  // namespace
}  // namespace glmbslam::eval
