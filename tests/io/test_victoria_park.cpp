// Victoria Park reader: the real files, the GPS outlier rule, and rejection of missing / mis-shaped
// variables.
#include <cstdio>
#include <functional>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/mat_reader.hpp"
#include "io/victoria_park.hpp"
#include "support/test_data.hpp"

namespace glmbslam::io {
namespace {

TEST(VictoriaPark, ReadsTheRealFiles) {
  GLMBSLAM_REQUIRE_DATA(folder, "victoria_park");
  ASSERT_TRUE(is_victoria_park_folder(folder));
  const VictoriaParkData d = read_victoria_park(folder);
  EXPECT_EQ(d.odometry.time_s.size(), 61945u);
  EXPECT_EQ(d.gps_raw.size(), 4466u);
  ASSERT_EQ(d.scans.size(), 7249u);
  std::size_t detections = 0, most = 0;
  for (const auto& s : d.scans) {
    detections += static_cast<std::size_t>(s.detections.cols());
    most = std::max(most, static_cast<std::size_t>(s.detections.cols()));
  }
  EXPECT_EQ(detections, 52974u);
  EXPECT_EQ(most, 18u);
  // Laser and odometry share one clock, in seconds, over the 1549 s run.
  EXPECT_NEAR(d.odometry.time_s.front(), 21.94, 1e-9);
  EXPECT_NEAR(d.scans.back().time_s - d.scans.front().time_s, 1548.4, 1.0);
  EXPECT_NEAR(d.gps_raw.front().position.x(), -67.6493, 1e-4);
  EXPECT_NEAR(d.gps_raw.front().position.y(), -41.7142, 1e-4);
  // README: 81 gaps over 1 s and ~41 jumps faster than 10 m/s.
  EXPECT_EQ(d.gps.gaps, 81u);
  EXPECT_GE(d.gps.jumps, 30u);
  EXPECT_LE(d.gps.jumps, 60u);
  EXPECT_GT(d.gps.fixes.size(), 4000u);
  std::printf("GPS: %zu raw, %zu gaps, %zu jumps rejected, %zu in short segments, %zu kept\n",
              d.gps_raw.size(), d.gps.gaps, d.gps.jumps, d.gps.short_segments, d.gps.fixes.size());
  for (std::size_t i = 1; i < d.gps.fixes.size(); ++i) {
    const double dt = d.gps.fixes[i].time_s - d.gps.fixes[i - 1].time_s;
    ASSERT_GT(dt, 0.0);
    if (dt <= 1.0) {
      EXPECT_LE((d.gps.fixes[i].position - d.gps.fixes[i - 1].position).norm() / dt, 10.0);
    }
  }
}

std::vector<GpsFix> track(int n, double t0, Eigen::Vector2d p0, double speed) {
  std::vector<GpsFix> out;
  for (int i = 0; i < n; ++i) out.push_back({t0 + 0.2 * i, p0 + Eigen::Vector2d(speed * 0.2 * i, 0.0)});
  return out;
}

TEST(VictoriaPark, GpsFilterRemovesSpikesStepsAndIsolatedFixes) {
  auto fixes = track(20, 0.0, {0, 0}, 5.0);
  fixes[7].position.y() += 30.0;                   // a spike
  auto after_gap = track(1, 10.0, {100, 0}, 5.0);  // isolated fix after a gap
  auto later = track(10, 20.0, {200, 0}, 5.0);     // a good segment after another gap
  fixes.insert(fixes.end(), after_gap.begin(), after_gap.end());
  fixes.insert(fixes.end(), later.begin(), later.end());
  const GpsFilterResult r = filter_gps_outliers(fixes);
  EXPECT_EQ(r.gaps, 2u);
  EXPECT_EQ(r.jumps, 1u);
  EXPECT_EQ(r.short_segments, 1u);
  EXPECT_EQ(r.fixes.size(), 29u);
  for (const auto& f : r.fixes) EXPECT_EQ(f.position.y(), 0.0);
}

TEST(VictoriaPark, RejectsMissingOrMisShapedVariables) {
  const auto dir = test::fresh_temp_dir("victoria_park");
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(5, 0.0, 100.0);
  const Eigen::VectorXd z = Eigen::VectorXd::Zero(5);
  auto write_dr = [&](std::vector<MatVariable> v) { write_mat_file(dir / kVictoriaParkOdometryFile, v); };
  auto write_gps = [&](std::vector<MatVariable> v) { write_mat_file(dir / kVictoriaParkGpsFile, v); };
  auto write_laser = [&](std::vector<MatVariable> v) {
    write_mat_file(dir / kVictoriaParkDetectionsFile, v);
  };
  const auto good_dr = std::vector<MatVariable>{MatVariable::matrix_variable("time", t),
                                                MatVariable::matrix_variable("speed", z),
                                                MatVariable::matrix_variable("steering", z)};
  const auto good_gps = std::vector<MatVariable>{MatVariable::matrix_variable("timeGps", t),
                                                 MatVariable::matrix_variable("Lo_m", z),
                                                 MatVariable::matrix_variable("La_m", z)};
  const Eigen::MatrixXd scan = Eigen::MatrixXd::Ones(3, 2);
  const auto good_laser =
      std::vector<MatVariable>{MatVariable::matrix_variable("TLsr", Eigen::RowVector2d(0.1, 0.2)),
                               MatVariable::cell_variable("zt", {scan, Eigen::MatrixXd(0, 0)})};
  auto message = [&]() -> std::string {
    try {
      read_victoria_park(dir);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  auto reset = [&] {
    write_dr(good_dr);
    write_gps(good_gps);
    write_laser(good_laser);
  };
  reset();
  EXPECT_EQ(message(), "");
  EXPECT_EQ(read_victoria_park(dir).scans[1].detections.cols(), 0);

  write_dr({good_dr[0], good_dr[1]});
  EXPECT_NE(message().find("'steering' is missing"), std::string::npos);
  write_dr({good_dr[0], good_dr[1], MatVariable::matrix_variable("steering", Eigen::VectorXd::Zero(4))});
  EXPECT_NE(message().find("'steering' has 4 elements"), std::string::npos);
  write_dr({good_dr[0], good_dr[1], MatVariable::matrix_variable("steering", Eigen::MatrixXd::Zero(5, 2))});
  EXPECT_NE(message().find("'steering' must be a vector"), std::string::npos);
  reset();
  write_gps({good_gps[0], good_gps[1]});
  EXPECT_NE(message().find("'La_m' is missing"), std::string::npos);
  EXPECT_NE(message().find(kVictoriaParkGpsFile), std::string::npos);
  reset();
  write_laser({good_laser[0], MatVariable::cell_variable("zt", {scan, Eigen::MatrixXd::Ones(2, 2)})});
  EXPECT_NE(message().find("'zt{2}' must be 3xany, found 2x2"), std::string::npos);
  write_laser({good_laser[0], MatVariable::cell_variable("zt", {scan})});
  EXPECT_NE(message().find("'zt' must have 2 cells"), std::string::npos);
  write_laser({good_laser[0], MatVariable::matrix_variable("zt", scan)});
  EXPECT_NE(message().find("'zt' must be a cell array"), std::string::npos);
  write_laser({good_laser[1]});
  EXPECT_NE(message().find("'TLsr' is missing"), std::string::npos);
  reset();
  // without the GPS file (the reference, not an input) the data read without fixes
  std::filesystem::remove(dir / kVictoriaParkGpsFile);
  EXPECT_EQ(message(), "");
  const VictoriaParkData without_gps = read_victoria_park(dir);
  EXPECT_TRUE(without_gps.gps_raw.empty());
  EXPECT_TRUE(without_gps.gps.fixes.empty());
  EXPECT_EQ(without_gps.scans.size(), 2u);
}

}  // namespace
}  // namespace glmbslam::io
