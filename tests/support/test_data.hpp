#pragma once
// Locating the shared real data for tests: GLMBSLAM_DATA overrides the compiled-in default (../shared/data).
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace glmbslam::test {

/// Root of the shared data (GLMBSLAM_DATA or the default next to the project).
inline std::filesystem::path shared_data_dir() {
  if (const char* env = std::getenv("GLMBSLAM_DATA"); env != nullptr && *env != '\0') {
    return std::filesystem::path(env);
  }
  return std::filesystem::path(GLMBSLAM_DEFAULT_DATA_DIR);
}

/// Path of the glmbslam executable built with the tests.
inline std::filesystem::path glmbslam_binary() {
  return std::filesystem::path(GLMBSLAM_BINARY);
}

/// A fresh, empty temporary directory unique to the running test.
inline std::filesystem::path fresh_temp_dir(const std::string& tag) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = tag;
  if (info != nullptr) {
    name += std::string("_") + info->test_suite_name() + "_" + info->name();
  }
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  auto dir = std::filesystem::temp_directory_path() / ("glmbslam_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace glmbslam::test

/// Skips the current test with a clear message when a file or folder of the shared data is absent.
#define GLMBSLAM_REQUIRE_DATA(var, relative)                                                       \
  const std::filesystem::path var = glmbslam::test::shared_data_dir() / (relative);                \
  if (!std::filesystem::exists(var)) {                                                             \
    GTEST_SKIP() << "shared data not found: " << var.string()                                      \
                 << " (set GLMBSLAM_DATA to the folder holding kitti_odometry/, kitti_raw/, ...)"; \
  }
