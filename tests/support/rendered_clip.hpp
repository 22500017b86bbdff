#pragma once
// The short rendered stereo clip of the end-to-end stereo tests (built-in trajectory, frames 0..39, with
// depth maps), in the KITTI odometry layout: <root>/poses/00.txt and <root>/sequences/00.
// ctest runs each test in its own process, possibly concurrently: the clip is rendered once into a shared
// cache folder (rendered into a private folder, then renamed, so no process sees a half-written clip).
#include <cstddef>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

#include "sim/kitti_sequence_writer.hpp"

namespace glmbslam::test {

inline constexpr std::size_t kClipFrames = 40;

/// The clip's root folder, rendered on first use.
inline std::filesystem::path rendered_stereo_clip() {
  namespace fs = std::filesystem;
  const fs::path clip = fs::temp_directory_path() / "glmbslam_test_stereo_clip_v1";
  if (!fs::exists(clip / "poses" / "00.txt")) {
    const fs::path mine =
        fs::temp_directory_path() / ("glmbslam_test_stereo_clip_" + std::to_string(::getpid()));
    fs::remove_all(mine);
    sim::SequenceRenderOptions o;
    o.out_dir = mine.string();
    o.frames = "0:" + std::to_string(kClipFrames);
    o.depth = true;
    sim::render_kitti_sequence(o);
    std::error_code ec;
    fs::rename(mine, clip, ec);  // fails if another process got there first: use theirs
    if (ec) fs::remove_all(mine);
  }
  return clip;
}

}  // namespace glmbslam::test
