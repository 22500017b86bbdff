#pragma once
// Locating the shared real data for tests: GLMBSLAM_DATA overrides the compiled-in default (../shared/data).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

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

/// Removes the folders and files registered by remove_after_test() (fresh_temp_dir()'s among them) when the
/// test ends, unless it failed: those are kept for inspection and their paths printed.
class TempDirCleanup : public ::testing::EmptyTestEventListener {
 public:
  static std::vector<std::filesystem::path>& pending() {
    static std::vector<std::filesystem::path> dirs;
    return dirs;
  }
  void OnTestEnd(const ::testing::TestInfo& info) override {
    for (const auto& dir : pending()) {
      if (info.result() != nullptr && info.result()->Failed()) {
        std::fprintf(stderr, "test output kept in %s\n", dir.string().c_str());
      } else {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
      }
    }
    pending().clear();
  }
  /// Installs the listener once per test binary (from fresh_temp_dir(), inside a running test).
  static void install() {
    static const bool installed = [] {
      ::testing::UnitTest::GetInstance()->listeners().Append(new TempDirCleanup);  // gtest owns it
      return true;
    }();
    (void)installed;
  }
};

/// Removes `path` (a file or a folder) when the running test ends, unless it fails.
inline void remove_after_test(const std::filesystem::path& path) {
  TempDirCleanup::install();
  TempDirCleanup::pending().push_back(path);
}

/// A fresh, empty temporary directory unique to the running test, removed when the test passes.
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
  if (info != nullptr) remove_after_test(dir);
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
