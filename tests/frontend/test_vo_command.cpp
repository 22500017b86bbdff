// `glmbslam vo` end to end on a few frames of KITTI raw drive 0001 copied into a temporary folder, with a
// corrupted right image (graceful fallback) and with a missing right image (clear error, exit code 2).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.hpp"

namespace glmbslam::frontend {
namespace {

namespace fs = std::filesystem;

/// Copies the first `frames` frames of drive 0001 (images, oxts, timestamps, calibration) into `root`.
fs::path copy_drive(const fs::path& source_drive, const fs::path& root, int frames) {
  const fs::path date = root / "2011_09_26";
  const fs::path drive = date / source_drive.filename();
  for (const char* f : {"calib_cam_to_cam.txt", "calib_imu_to_velo.txt", "calib_velo_to_cam.txt"}) {
    fs::create_directories(date);
    fs::copy_file(source_drive.parent_path() / f, date / f);
  }
  for (const std::string sub : {"image_00", "image_01", "oxts"}) {
    fs::create_directories(drive / sub / "data");
    std::ifstream in(source_drive / sub / "timestamps.txt");
    std::ofstream out(drive / sub / "timestamps.txt");
    std::string line;
    for (int i = 0; i < frames && std::getline(in, line); ++i) out << line << '\n';
    for (int i = 0; i < frames; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "%010d.%s", i, sub == "oxts" ? "txt" : "png");
      fs::copy_file(source_drive / sub / "data" / name, drive / sub / "data" / name);
    }
  }
  if (fs::exists(source_drive / "oxts" / "dataformat.txt")) {
    fs::copy_file(source_drive / "oxts" / "dataformat.txt", drive / "oxts" / "dataformat.txt");
  }
  return drive;
}

int run(const std::string& args, const fs::path& log) {
  const std::string cmd =
      glmbslam::test::glmbslam_binary().string() + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int count_lines(const fs::path& p) {
  std::ifstream in(p);
  int n = 0;
  std::string line;
  while (std::getline(in, line)) n += !line.empty();
  return n;
}

TEST(VoCommand, CorruptedRightImageFallsBackAndKeepsOnePosePerFrame) {
  GLMBSLAM_REQUIRE_DATA(source, "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync");
  if (!fs::exists(glmbslam::test::glmbslam_binary())) GTEST_SKIP() << "glmbslam binary not built";
  const fs::path root = glmbslam::test::fresh_temp_dir("vo_cmd");
  const fs::path drive = copy_drive(source, root, 6);
  std::ofstream(drive / "image_01" / "data" / "0000000003.png", std::ios::trunc) << "not a png";
  const fs::path out = root / "out";
  ASSERT_EQ(run("vo " + drive.string() + " --out " + out.string(), root / "log.txt"), 0)
      << read_all(root / "log.txt");
  EXPECT_EQ(count_lines(out / "vo_trajectory.txt"), 6);
  const std::string frames = read_all(out / "vo_frames.csv");
  EXPECT_NE(frames.find("3,missing_image"), std::string::npos) << frames;
  EXPECT_NE(frames.find("4,tracked"), std::string::npos) << frames;
  EXPECT_TRUE(fs::exists(out / "metrics.json"));
  EXPECT_TRUE(fs::exists(out / "vo_features.png"));
  EXPECT_NE(read_all(root / "log.txt").find("0000000003.png"), std::string::npos);
}

TEST(VoCommand, MissingRightImageIsAClearError) {
  GLMBSLAM_REQUIRE_DATA(source, "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync");
  if (!fs::exists(glmbslam::test::glmbslam_binary())) GTEST_SKIP() << "glmbslam binary not built";
  const fs::path root = glmbslam::test::fresh_temp_dir("vo_cmd");
  const fs::path drive = copy_drive(source, root, 4);
  fs::remove(drive / "image_01" / "data" / "0000000002.png");
  const fs::path out = root / "out";
  EXPECT_EQ(run("vo " + drive.string() + " --out " + out.string(), root / "log.txt"), 2);
  const std::string log = read_all(root / "log.txt");
  EXPECT_NE(log.find("image_0"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out / "vo_trajectory.txt"));
}

TEST(VoCommand, BadFrameRangeIsAnError) {
  GLMBSLAM_REQUIRE_DATA(source, "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync");
  if (!fs::exists(glmbslam::test::glmbslam_binary())) GTEST_SKIP() << "glmbslam binary not built";
  const fs::path root = glmbslam::test::fresh_temp_dir("vo_cmd");
  EXPECT_NE(
      run("vo " + source.string() + " --frames 50:40 --out " + (root / "out").string(), root / "log.txt"), 0);
}

}  // namespace
}  // namespace glmbslam::frontend
