#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "eval/eval_plots.hpp"
#include "eval/line_plot.hpp"
#include "support/test_data.hpp"

namespace glmbslam::eval {
namespace {

/// Width and height from a PNG's IHDR chunk (big-endian at bytes 16..23).
std::pair<int, int> png_size(const std::vector<std::uint8_t>& png) {
  auto be32 = [&](size_t o) { return (png[o] << 24) | (png[o + 1] << 16) | (png[o + 2] << 8) | png[o + 3]; };
  return {be32(16), be32(20)};
}

TEST(NiceTicks, StepsOfOneTwoFive) {
  EXPECT_EQ(nice_ticks(0.0, 10.0, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  const auto t = nice_ticks(-0.37, 0.81, 6);
  ASSERT_GE(t.size(), 2u);
  EXPECT_NEAR(t[1] - t[0], 0.2, 1e-12);
  EXPECT_GE(t.front(), -0.37);
  EXPECT_LE(t.back(), 0.81);
  EXPECT_TRUE(nice_ticks(1.0, 1.0).empty());
}

TEST(LinePlot, RendersPngOfRequestedSize) {
  LinePlot p("title", "x [m]", "y [m]");
  p.add_series({0, 1, 2, NAN, 4}, {0, 1, 4, 9, 16}, colours::kBlue, "quadratic", SeriesStyle::kLineMarkers);
  p.add_series({0, 4}, {16, 0}, colours::kRed, "");
  const auto png = p.render_png(640, 480);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png[1], 'P');
  EXPECT_EQ(png[2], 'N');
  EXPECT_EQ(png[3], 'G');
  EXPECT_EQ(png_size(png), std::make_pair(640, 480));
  EXPECT_THROW(p.add_series({0, 1}, {0}, colours::kBlack, "bad"), std::invalid_argument);
}

TEST(LinePlot, EmptyPlotAndSaveErrors) {
  LinePlot p("empty", "x", "y");
  EXPECT_NO_THROW(p.render_png());
  EXPECT_THROW(p.save_png("/nonexistent_folder_for_glmbslam_test/plot.png"), InputError);
}

TEST(EvalPlots, WritesTheFourPlots) {
  PoseList gt, est;
  for (int i = 0; i < 300; ++i) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(10.0 * std::sin(i * 0.02), 0.0, 1.0 * i);
    gt.push_back(T);
    T.translation().x() += 0.01 * i;
    est.push_back(T);
  }
  const TrajectoryEvaluation e = evaluate_trajectory(gt, est);
  const auto dir = test::fresh_temp_dir("eval_plots");
  const auto files = write_evaluation_plots((dir / "plots").string(), gt, est, e);
  ASSERT_EQ(files.size(), 4u);
  for (const auto& f : files) {
    EXPECT_TRUE(std::filesystem::exists(f)) << f;
    EXPECT_GT(std::filesystem::file_size(f), 1000u) << f;
  }
}

}  // namespace
}  // namespace glmbslam::eval
