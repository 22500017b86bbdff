// phdslam3 scenario: reading Environment_SLAM.mat with validation, and the per-run regeneration recipe.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/lie.hpp"
#include "io/mat_reader.hpp"
#include "sim/scenario_phdslam3.hpp"
#include "support/test_data.hpp"

namespace glmbslam::sim {
namespace {

TEST(ScenarioPhdSlam3, ReadsTheBenchmarkAndItsMotionConvention) {
  GLMBSLAM_REQUIRE_DATA(path, "phdslam3_synthetic/Environment_SLAM.mat");
  const PhdSlam3Environment env = load_phdslam3_environment(path);
  EXPECT_EQ(env.landmarks.size(), 160u);
  ASSERT_EQ(env.poses.size(), 4000u);
  EXPECT_DOUBLE_EQ(env.dt, 1.0);
  EXPECT_NEAR(env.poses[0](2), -5.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(std::sqrt(env.odometry_noise(0, 0)), 0.8, 1e-9);
  EXPECT_NEAR(std::sqrt(env.odometry_noise(1, 1)), 0.5 * M_PI / 180.0, 1e-6);
  // The ground truth is the unicycle convention of scenario2d.hpp driven by Robot_Control(:, k).
  double max_err = 0.0;
  for (std::size_t k = 1; k < env.poses.size(); ++k) {
    const Eigen::Vector3d p = unicycle_step(env.poses[k - 1], env.controls[k], env.dt);
    max_err = std::max(max_err, (p.head<2>() - env.poses[k].head<2>()).norm());
    max_err = std::max(max_err, std::abs(wrap_angle(p(2) - env.poses[k](2))));
  }
  EXPECT_LT(max_err, 1e-9);
}

TEST(ScenarioPhdSlam3, RegenerationFollowsTheRecipe) {
  GLMBSLAM_REQUIRE_DATA(path, "phdslam3_synthetic/Environment_SLAM.mat");
  const PhdSlam3Environment env = load_phdslam3_environment(path);
  const Scenario2D s = make_phdslam3_scenario(env, 3);
  const Scenario2D again = make_phdslam3_scenario(env, 3);
  const Scenario2D other = make_phdslam3_scenario(env, 4);
  ASSERT_EQ(s.steps(), 4000u);
  EXPECT_NEAR(s.sensor.clutter_intensity(), 5.0 / (150.0 * M_PI), 1e-12);
  std::size_t visible = 0, detections = 0, clutter = 0, differ = 0;
  Eigen::Vector2d odo_sum = Eigen::Vector2d::Zero(), odo_sq = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < s.steps(); ++k) {
    ASSERT_EQ(s.measurements[k].size(), again.measurements[k].size());
    for (std::size_t j = 0; j < s.measurements[k].size(); ++j)
      ASSERT_EQ(s.measurements[k][j], again.measurements[k][j]);
    differ += s.measurements[k].size() != other.measurements[k].size() ? 1 : 0;
    visible += visible_landmarks(s.poses[k], s.landmarks, s.sensor).size();
    for (std::size_t j = 0; j < s.measurements[k].size(); ++j) {
      const int src = s.measurement_sources[k][j];
      if (src < 0) {
        ++clutter;
        continue;
      }
      ++detections;
      const Eigen::Vector2d clean = range_bearing(s.poses[k], s.landmarks[static_cast<std::size_t>(src)]);
      EXPECT_LT(std::abs(s.measurements[k][j](0) - clean(0)), 8.0);
      EXPECT_LT(std::abs(wrap_angle(s.measurements[k][j](1) - clean(1))), 3.0 * M_PI / 180.0);
    }
    if (k > 0) {
      const Eigen::Vector2d e = s.controls[k] - env.controls[k];
      odo_sum += e;
      odo_sq += e.cwiseProduct(e);
    }
  }
  const double n = static_cast<double>(s.steps());
  EXPECT_GT(differ, 1000u);
  EXPECT_NEAR(static_cast<double>(detections) / static_cast<double>(visible), 0.95, 0.01);
  EXPECT_NEAR(static_cast<double>(clutter) / n, 4.75, 0.2);  // Poisson(5) thinned by 0.95
  EXPECT_NEAR(std::sqrt(odo_sq(0) / (n - 1)), 0.8, 0.03);
  EXPECT_NEAR(std::sqrt(odo_sq(1) / (n - 1)), 0.5 * M_PI / 180.0, 0.03 * 0.5 * M_PI / 180.0);
  EXPECT_NEAR(odo_sum(0) / (n - 1), 0.0, 0.05);
}

TEST(ScenarioPhdSlam3, RejectsMissingOrMisShapedVariables) {
  const auto dir = test::fresh_temp_dir("phdslam3");
  const Eigen::MatrixXd lm = Eigen::MatrixXd::Ones(4, 5);
  const Eigen::MatrixXd gt = Eigen::MatrixXd::Zero(3, 10);
  const Eigen::MatrixXd ctl = Eigen::MatrixXd::Zero(2, 10);
  const Eigen::MatrixXd q = Eigen::Matrix2d::Identity();
  const Eigen::MatrixXd t = Eigen::MatrixXd::Ones(1, 1);
  using io::MatVariable;
  auto write = [&](const std::vector<MatVariable>& vars) {
    const auto f = dir / "env.mat";
    io::write_mat_file(f, vars);
    return f;
  };
  auto message = [&](const std::vector<MatVariable>& vars) -> std::string {
    try {
      load_phdslam3_environment(write(vars));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const auto good =
      std::vector<MatVariable>{MatVariable::matrix_variable("Landmark_Groundtruth", lm),
                               MatVariable::matrix_variable("Robot_Groundtruth", gt),
                               MatVariable::matrix_variable("Robot_Control", ctl),
                               MatVariable::matrix_variable("Qodo", q), MatVariable::matrix_variable("T", t)};
  EXPECT_EQ(message(good), "");
  auto without = [&](const std::string& name) {
    std::vector<MatVariable> v;
    for (const auto& x : good)
      if (x.name != name) v.push_back(x);
    return v;
  };
  auto with = [&](const std::string& name, const Eigen::MatrixXd& m) {
    auto v = without(name);
    v.push_back(MatVariable::matrix_variable(name, m));
    return v;
  };
  for (const char* name : {"Landmark_Groundtruth", "Robot_Groundtruth", "Robot_Control", "Qodo", "T"}) {
    EXPECT_NE(message(without(name)).find(std::string("'") + name + "' is missing"), std::string::npos)
        << name;
  }
  EXPECT_NE(message(with("Landmark_Groundtruth", Eigen::MatrixXd::Ones(4, 3)))
                .find("'Landmark_Groundtruth' must be"),
            std::string::npos);
  EXPECT_NE(message(with("Robot_Control", Eigen::MatrixXd::Zero(2, 9))).find("'Robot_Control' must be 2x10"),
            std::string::npos);
  EXPECT_NE(message(with("Qodo", Eigen::Matrix2d(Eigen::Vector2d(1, -1).asDiagonal()))).find("'Qodo'"),
            std::string::npos);
  EXPECT_NE(message(with("T", Eigen::MatrixXd::Zero(1, 1))).find("'T'"), std::string::npos);
  auto cell = without("Robot_Groundtruth");
  cell.push_back(MatVariable::cell_variable("Robot_Groundtruth", {gt}));
  EXPECT_NE(message(cell).find("'Robot_Groundtruth' must be a numeric matrix"), std::string::npos);
}

}  // namespace
}  // namespace glmbslam::sim
