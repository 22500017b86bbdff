#pragma once
// Builders of small fake KITTI datasets in a temporary folder (cv::imwrite), and an InputError matcher.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.hpp"

namespace glmbslam::test {

namespace fs = std::filesystem;

inline void write_text(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file);
  out << text;
}

/// A gray image whose pixel (0,0) encodes `tag` (so a test can tell frames apart).
inline void write_image(const fs::path& file, int width, int height, int tag) {
  fs::create_directories(file.parent_path());
  cv::Mat img(height, width, CV_8UC1, cv::Scalar(100));
  img.at<std::uint8_t>(0, 0) = static_cast<std::uint8_t>(tag);
  ASSERT_TRUE(cv::imwrite(file.string(), img)) << file;
}

inline std::string six_digits(int i) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%06d", i);
  return buf;
}

inline std::string ten_digits(int i) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%010d", i);
  return buf;
}

constexpr int kFakeWidth = 40;
constexpr int kFakeHeight = 30;

/// root/sequences/07/{image_0,image_1,calib.txt,times.txt} + root/poses/07.txt; returns the sequence folder.
/// Pose i is a translation of (0, 0, i) m; times are 0.1·i s; fx = 700, cx = 20, cy = 15, baseline 0.5 m.
inline fs::path make_fake_kitti_sequence(const fs::path& root, int frames, bool with_poses = true) {
  const fs::path seq = root / "sequences" / "07";
  std::string times;
  std::string poses;
  for (int i = 0; i < frames; ++i) {
    write_image(seq / "image_0" / (six_digits(i) + ".png"), kFakeWidth, kFakeHeight, i);
    write_image(seq / "image_1" / (six_digits(i) + ".png"), kFakeWidth, kFakeHeight, 100 + i);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%e\n", 0.1 * i);
    times += buf;
    std::snprintf(buf, sizeof buf, "1 0 0 0 0 1 0 0 0 0 1 %d\n", i);
    poses += buf;
  }
  write_text(seq / "times.txt", times);
  write_text(seq / "calib.txt",
             "P0: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P1: 7.0e+02 0 2.0e+01 -3.5e+02 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P2: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P3: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  if (with_poses) write_text(root / "poses" / "07.txt", poses);
  return seq;
}

/// Runs `f` and checks that it throws InputError whose message contains `file_part` (the file it must name)
/// and `problem_part`.
inline void expect_input_error(const std::function<void()>& f, const std::string& file_part,
                               const std::string& problem_part) {
  try {
    f();
    ADD_FAILURE() << "expected InputError mentioning '" << file_part << "' and '" << problem_part << "'";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file_part), std::string::npos)
        << "message does not name '" << file_part << "': " << what;
    EXPECT_NE(what.find(problem_part), std::string::npos)
        << "message does not state '" << problem_part << "': " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "message is not one line: " << what;
  }
}

}  // namespace glmbslam::test
