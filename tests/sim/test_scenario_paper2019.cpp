// paper2019 scenario: the paper's parameters, a closed loop revisited at the end, one realisation per clutter
// rate.
#include <gtest/gtest.h>

#include "core/lie.hpp"
#include "sim/scenario_paper2019.hpp"

namespace glmbslam::sim {
namespace {

TEST(ScenarioPaper2019, ParametersOfThePaper) {
  const Scenario2D s = make_paper2019_scenario({});
  EXPECT_EQ(s.landmarks.size(), 23u);
  EXPECT_GE(s.steps(), 150u);
  EXPECT_LE(s.steps(), 200u);
  EXPECT_DOUBLE_EQ(s.sensor.max_range, 3.0);
  EXPECT_DOUBLE_EQ(s.sensor.max_bearing, M_PI);
  EXPECT_DOUBLE_EQ(s.sensor.detection_probability, 0.7);
  EXPECT_NEAR(std::sqrt(s.sensor.measurement_noise(0, 0)), 0.05, 1e-12);
  EXPECT_NEAR(std::sqrt(s.sensor.measurement_noise(1, 1)), 0.5 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(std::sqrt(s.control_noise(0, 0)), 0.1, 1e-12);
  EXPECT_NEAR(std::sqrt(s.control_noise(1, 1)), 2.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(s.motion, MotionKind::kSteering);
  EXPECT_NEAR(s.sensor.clutter_intensity(), 5.0 / (3.0 * 2.0 * M_PI), 1e-12);
  // 1 m/s ground-truth speed.
  for (std::size_t k = 1; k < s.steps(); ++k) {
    EXPECT_NEAR((s.poses[k].head<2>() - s.poses[k - 1].head<2>()).norm(), s.dt, 1e-9);
    EXPECT_EQ(s.true_controls[k](0), 1.0);
  }
}

TEST(ScenarioPaper2019, LoopClosesAndIsRevisitedBetweenSteps125And150) {
  const Scenario2D s = make_paper2019_scenario({});
  // Ground truth follows the unicycle convention exactly.
  for (std::size_t k = 1; k < s.steps(); ++k) {
    const Eigen::Vector3d p = steering_step(s.poses[k - 1], s.true_controls[k], s.dt, s.wheel_base);
    EXPECT_NEAR((p - s.poses[k]).norm(), 0.0, 1e-12);
  }
  // After one lap (124 steps) the robot is back at the start with the start heading.
  EXPECT_NEAR(s.poses[124].head<2>().norm(), 0.0, 1e-9);
  EXPECT_NEAR(wrap_angle(s.poses[124](2) - s.poses[0](2)), 0.0, 1e-9);
  // During 125..150 it sees landmarks that it saw during the first 30 steps.
  std::vector<int> early;
  for (int k = 0; k < 30; ++k) {
    for (int i : visible_landmarks(s.poses[k], s.landmarks, s.sensor)) early.push_back(i);
  }
  int revisited = 0;
  for (int k = 125; k <= 150; ++k) {
    for (int i : visible_landmarks(s.poses[k], s.landmarks, s.sensor)) {
      revisited += std::count(early.begin(), early.end(), i) > 0 ? 1 : 0;
    }
  }
  EXPECT_GT(revisited, 25);
  // Every landmark is seen at some step, and most steps see at least one landmark.
  std::vector<int> seen(s.landmarks.size(), 0);
  int steps_with_landmarks = 0;
  for (const auto& p : s.poses) {
    const auto v = visible_landmarks(p, s.landmarks, s.sensor);
    steps_with_landmarks += v.empty() ? 0 : 1;
    for (int i : v) seen[static_cast<std::size_t>(i)] = 1;
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 23);
  EXPECT_GT(steps_with_landmarks, static_cast<int>(0.9 * static_cast<double>(s.steps())));
}

TEST(ScenarioPaper2019, OneRealisationPerClutterRate) {
  Paper2019Options a;
  a.clutter_rate = 1.0;
  Paper2019Options b;
  b.clutter_rate = 15.0;
  const Scenario2D s1 = make_paper2019_scenario(a);
  const Scenario2D s1_again = make_paper2019_scenario(a);
  const Scenario2D s15 = make_paper2019_scenario(b);
  // Deterministic.
  for (std::size_t k = 0; k < s1.steps(); ++k) {
    ASSERT_EQ(s1.measurements[k].size(), s1_again.measurements[k].size());
    for (std::size_t j = 0; j < s1.measurements[k].size(); ++j)
      EXPECT_EQ(s1.measurements[k][j], s1_again.measurements[k][j]);
  }
  // Same odometry, landmarks and landmark detections for every clutter rate; only the clutter differs.
  std::size_t clutter1 = 0, clutter15 = 0, detections = 0;
  for (std::size_t k = 0; k < s1.steps(); ++k) {
    EXPECT_EQ(s1.controls[k], s15.controls[k]);
    std::vector<std::pair<int, Eigen::Vector2d>> d1, d15;
    for (std::size_t j = 0; j < s1.measurements[k].size(); ++j) {
      if (s1.measurement_sources[k][j] >= 0)
        d1.emplace_back(s1.measurement_sources[k][j], s1.measurements[k][j]);
      else
        ++clutter1;
    }
    for (std::size_t j = 0; j < s15.measurements[k].size(); ++j) {
      if (s15.measurement_sources[k][j] >= 0)
        d15.emplace_back(s15.measurement_sources[k][j], s15.measurements[k][j]);
      else
        ++clutter15;
    }
    auto by_id = [](const auto& x, const auto& y) { return x.first < y.first; };
    std::sort(d1.begin(), d1.end(), by_id);
    std::sort(d15.begin(), d15.end(), by_id);
    ASSERT_EQ(d1.size(), d15.size());
    for (std::size_t j = 0; j < d1.size(); ++j) {
      EXPECT_EQ(d1[j].first, d15[j].first);
      EXPECT_EQ(d1[j].second, d15[j].second);
      // Detection noise is consistent with R (10σ bound).
      const Eigen::Vector2d clean =
          range_bearing(s1.poses[k], s1.landmarks[static_cast<std::size_t>(d1[j].first)]);
      EXPECT_LT(std::abs(d1[j].second(0) - clean(0)), 0.5);
      EXPECT_LT(std::abs(wrap_angle(d1[j].second(1) - clean(1))), 5.0 * M_PI / 180.0);
    }
    detections += d1.size();
  }
  const double steps = static_cast<double>(s1.steps());
  // Poisson means over the steps, within 5 standard errors (sqrt(λ / steps)).
  EXPECT_NEAR(static_cast<double>(clutter1) / steps, 1.0, 5.0 * std::sqrt(1.0 / steps));
  EXPECT_NEAR(static_cast<double>(clutter15) / steps, 15.0, 5.0 * std::sqrt(15.0 / steps));
  // p_D = 0.7: detections / visible landmark-steps.
  std::size_t visible = 0;
  for (const auto& p : s1.poses) visible += visible_landmarks(p, s1.landmarks, s1.sensor).size();
  EXPECT_NEAR(static_cast<double>(detections) / static_cast<double>(visible), 0.7, 0.05);
  // Clutter lies in the field of view.
  for (std::size_t k = 0; k < s15.steps(); ++k) {
    for (const auto& z : s15.measurements[k]) {
      EXPECT_GE(z(0), 0.0);
      EXPECT_LE(z(0), 3.0 + 0.5);
      EXPECT_LE(std::abs(z(1)), M_PI + 1e-12);
    }
  }
}

TEST(ScenarioPaper2019, RejectsNegativeClutter) {
  Paper2019Options o;
  o.clutter_rate = -1.0;
  EXPECT_THROW(make_paper2019_scenario(o), std::invalid_argument);
}

}  // namespace
}  // namespace glmbslam::sim
