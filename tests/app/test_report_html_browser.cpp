// report.html as a user opens it: the glmbslam binary writes the reports of `run`, `vo` and `sim` on small
// inputs, headless Chromium loads each one offline, and the test fails on any console error or script error,
// checks every plot drew its traces (3D map and paths included) and that the screenshot is not blank.
// Skips with a message when Chromium is not installed (scripts/install_deps.sh --test installs it).
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "support/headless_browser.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

/// Runs the glmbslam binary with `args`; its output goes to `log`.
int glmbslam(const std::string& args, const fs::path& log) {
  const std::string command = "'" + test::glmbslam_binary().string() + "' --log-level warn " + args + " > '" +
                              log.string() + "' 2>&1";
  return std::system(command.c_str());
}

/// Fraction of saturated pixels (max − min channel > 60) in rows [y0, y1): plot lines, markers, colour
/// scales; the page background and text are grey.
double saturated_fraction(const cv::Mat& bgr, int y0, int y1) {
  std::size_t n = 0, total = 0;
  for (int y = y0; y < std::min(y1, bgr.rows); ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
      const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
      n += hi - lo > 60 ? 1 : 0;
      ++total;
    }
  }
  return total > 0 ? static_cast<double>(n) / static_cast<double>(total) : 0.0;
}

class ReportInBrowser : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = test::find_chromium();
    if (!chromium_) {
      GTEST_SKIP() << "chromium not found on PATH: the report.html browser test needs it (Debian package "
                      "'chromium'; scripts/install_deps.sh --test installs it)";
    }
    dir_ = test::fresh_temp_dir("report_browser");
  }
  void TearDown() override {
    if (!dir_.empty() && !HasFailure()) fs::remove_all(dir_);
  }

  /// Loads `page` and checks what every report must satisfy; returns the DOM.
  test::BrowserLoad check_page(const fs::path& page) {
    EXPECT_TRUE(fs::exists(page)) << page;
    EXPECT_LT(fs::file_size(page), 15u * 1024 * 1024) << "report.html must stay below 15 MB";
    const test::BrowserLoad load = test::load_in_chromium(*chromium_, page, dir_, 1300, 2000);
    EXPECT_EQ(load.exit_code, 0) << load.log;
    EXPECT_EQ(test::attribute_of(load.dom, "<body", "data-status"), "ready") << load.log;
    EXPECT_EQ(test::attribute_of(load.dom, "<body", "data-errors"), "0") << load.dom.substr(0, 4000);
    // Errors raised before the page's own error capture ran show only in Chromium's console log.
    EXPECT_EQ(load.log.find("Uncaught"), std::string::npos) << load.log;
    const std::string expected = test::attribute_of(load.dom, "<body", "data-expected-traces");
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(test::attribute_of(load.dom, "<body", "data-traces"), expected);
    const cv::Mat shot = cv::imread(load.screenshot.string());
    EXPECT_FALSE(shot.empty()) << "no screenshot";
    if (!shot.empty()) {
      // Below the navigation bar (blue links) only the plots are coloured: text and tables are grey.
      EXPECT_GT(saturated_fraction(shot, 40, shot.rows), 0.001) << "blank screenshot";
    }
    return load;
  }

  std::optional<fs::path> chromium_;
  fs::path dir_;
};

TEST_F(ReportInBrowser, StereoRunAndVoReportsDrawTheMapPathsAndErrors) {
  ASSERT_EQ(glmbslam("render --out '" + (dir_ / "clip").string() + "' --frames 0:30", dir_ / "render.log"),
            0);
  const fs::path sequence = dir_ / "clip" / "sequences" / "00";
  ASSERT_EQ(glmbslam("--threads 2 run '" + sequence.string() + "' --out '" + (dir_ / "run").string() + "'",
                     dir_ / "run.log"),
            0);
  const test::BrowserLoad run = check_page(dir_ / "run" / "report.html");
  // The first plot is the 3D view: landmarks, ground truth, VO and SLAM paths, all drawn by WebGL.
  EXPECT_EQ(test::attribute_of(run.dom, "class=\"plot", "data-traces"), "4");
  // 3D, top view, error along the path, t_rel, r_rel, ESS, landmarks over time
  EXPECT_EQ(test::attribute_of(run.dom, "<body", "data-plots"), "7");
  // The 3D view (top of the page, below the summary) is not blank.
  const cv::Mat shot = cv::imread(run.screenshot.string());
  if (!shot.empty()) {
    EXPECT_GT(saturated_fraction(shot, 250, 950), 0.003) << "3D view blank";
  }

  ASSERT_EQ(
      glmbslam("vo '" + sequence.string() + "' --out '" + (dir_ / "vo").string() + "'", dir_ / "vo.log"), 0);
  const test::BrowserLoad vo = check_page(dir_ / "vo" / "report.html");
  EXPECT_EQ(test::attribute_of(vo.dom, "class=\"plot", "data-traces"), "2");  // ground truth, VO
}

TEST_F(ReportInBrowser, SimReportDrawsRunsAndErrorsOverTime) {
  ASSERT_EQ(glmbslam("--threads 2 sim --scenario paper2019 --algorithm glmb2 --particles 2 --runs 2 "
                     "--max-steps 60 --no-plots --out '" +
                         (dir_ / "sim").string() + "'",
                     dir_ / "sim.log"),
            0);
  const test::BrowserLoad sim = check_page(dir_ / "sim" / "report.html");
  // per-run errors, trajectory and map, position RMSE, heading RMSE, OSPA
  EXPECT_EQ(test::attribute_of(sim.dom, "<body", "data-plots"), "5");
}

}  // namespace
}  // namespace glmbslam::app
