#include "app/ground_truth_output.hpp"

#include <algorithm>
#include <system_error>

#include <spdlog/spdlog.h>

#include "io/trajectory_io.hpp"

namespace glmbslam::app {

bool write_ground_truth_file(const std::filesystem::path& dir, const PoseList* ground_truth,
                             const std::vector<char>& mask) {
  const std::filesystem::path path = dir / "ground_truth.txt";
  const std::size_t frames = ground_truth ? ground_truth->size() : 0;
  const auto measured =
      mask.empty()
          ? frames
          : static_cast<std::size_t>(std::count_if(mask.begin(), mask.end(), [](char m) { return m != 0; }));
  if (ground_truth && measured == frames) {
    io::write_kitti_poses(path.string(), *ground_truth);
    return true;
  }
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  if (ground_truth) {
    spdlog::info(
        "ground truth measured on {} of {} frames: ground_truth.txt is written only when every frame has it "
        "(metrics.json evaluates those {})",
        measured, frames, measured);
  }
  return false;
}

}  // namespace glmbslam::app
