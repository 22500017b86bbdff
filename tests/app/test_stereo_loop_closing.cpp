// End to end: `glmbslam run --refine ml` with loop closing (refine.loop_closure, the default) on a rendered
// drive round a 25 m circle that comes back to its start: the revisit is detected, the pose graph keeps it,
// and the refined trajectory is closer to the truth than the VO it started from.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/run_options.hpp"
#include "core/progress.hpp"
#include "sim/kitti_sequence_writer.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

/// 260 frames round a circle of radius 25 m (240 frames a lap), the camera along the tangent.
void write_circle_poses(const fs::path& file) {
  std::ofstream out(file);
  for (int k = 0; k < 260; ++k) {
    const double a = 2.0 * M_PI * k / 240.0;
    const double c = std::cos(-a), s = std::sin(-a);
    const double t[3] = {25.0 * (1.0 - std::cos(a)), 0.0, 25.0 * std::sin(a)};
    const double T[12] = {c, 0.0, s, t[0], 0.0, 1.0, 0.0, t[1], -s, 0.0, c, t[2]};
    for (int i = 0; i < 12; ++i) out << (i ? " " : "") << T[i];
    out << "\n";
  }
}

TEST(StereoLoopClosing, TheRevisitOfARenderedCircleIsClosed) {
  ProgressReporter::set_enabled(false);
  const fs::path root =
      fs::temp_directory_path() / ("glmbslam_test_loop_closing_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  write_circle_poses(root / "circle.txt");
  sim::SequenceRenderOptions render;
  render.out_dir = (root / "render").string();
  render.poses_path = (root / "circle.txt").string();
  sim::render_kitti_sequence(render);

  RunOptions o;
  o.dataset = (root / "render" / "sequences" / "00").string();
  o.config_file = (fs::path(GLMBSLAM_SOURCE_DIR) / "config" / "kitti00-02.yaml").string();
  o.out_dir = (root / "out").string();
  o.refine = "ml";
  ASSERT_EQ(run_stereo(o), 0);
  std::ifstream in(root / "out" / "metrics.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const auto& r = j["refinement"];
  EXPECT_GE(r["loops_detected"].get<double>(), 1.0);
  EXPECT_GE(r["loops"].get<double>(), 1.0);  // kept by the pose graph
  const double refined = j["refined"]["ate"]["se3_rmse_m"].get<double>();
  const double vo = j["vo"]["ate"]["se3_rmse_m"].get<double>();
  EXPECT_LT(refined, vo) << "refined " << refined << " m, VO " << vo << " m";
  fs::remove_all(root);
}

}  // namespace
}  // namespace glmbslam::app
