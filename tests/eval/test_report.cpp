#include <fstream>

#include <gtest/gtest.h>

#include "eval/report.hpp"
#include "support/test_data.hpp"

namespace glmbslam::eval {
namespace {

PoseList line(int frames, double step) {
  PoseList poses;
  for (int i = 0; i < frames; ++i) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(0.0, 0.0, step * i);
    poses.push_back(T);
  }
  return poses;
}

TEST(Report, JsonHasTheDesignKeys) {
  const TrajectoryEvaluation e = evaluate_trajectory(line(201, 1.0), line(201, 1.01));
  const nlohmann::json j = to_json(e);
  EXPECT_EQ(j.at("frames").get<int>(), 201);
  EXPECT_NEAR(j.at("path_length_m").get<double>(), 200.0, 1e-9);
  EXPECT_NEAR(j.at("kitti").at("t_rel_percent").get<double>(), 1.01, 1e-4);
  EXPECT_TRUE(j.at("kitti").contains("r_rel_deg_per_100m"));
  EXPECT_EQ(j.at("kitti").at("segments").get<int>(), 10);
  ASSERT_EQ(j.at("kitti").at("per_length").size(), 8u);
  EXPECT_EQ(j.at("kitti").at("per_length")[0].at("length_m").get<double>(), 100.0);
  EXPECT_TRUE(j.at("kitti").at("per_length")[1].at("t_rel_percent").is_null());  // no 200 m segment
  EXPECT_GT(j.at("kitti_short").at("segments").get<int>(), 0);
  EXPECT_NEAR(j.at("ate").at("sim3_rmse_m").get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(j.at("ate").at("sim3_scale").get<double>(), 1.0 / 1.01, 1e-9);
  EXPECT_TRUE(j.at("ate").contains("se3_rmse_m"));
  EXPECT_EQ(j.at("rpe").at("delta_frames").get<int>(), 1);
  EXPECT_NEAR(j.at("rpe").at("trans_rmse_m").get<double>(), 0.01, 1e-9);
  EXPECT_EQ(j.at("rpe").at("by_distance")[0].at("delta_m").get<double>(), 100.0);
  const std::string table = format_table(e);
  EXPECT_NE(table.find("KITTI short"), std::string::npos);
  EXPECT_NE(table.find("Sim(3)"), std::string::npos);
  // Lengths no segment fits in are left out of the table (the JSON keeps them as null).
  EXPECT_NE(table.find("   100 m"), std::string::npos);
  EXPECT_EQ(table.find("   200 m"), std::string::npos);
}

TEST(Report, WritesJsonAtomically) {
  const auto dir = test::fresh_temp_dir("eval_report");
  const auto path = (dir / "metrics.json").string();
  write_json_file(path, to_json(evaluate_trajectory(line(30, 1.0), line(30, 1.0))));
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("frames").get<int>(), 30);
  EXPECT_TRUE(j.at("kitti").at("t_rel_percent").is_null());  // a 29 m path has no 100 m segment
  int files = 0;
  for ([[maybe_unused]] const auto& f : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);  // no temporary left behind
}

}  // namespace
}  // namespace glmbslam::eval
