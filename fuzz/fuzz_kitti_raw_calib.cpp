// KITTI raw date-level calibration (io::read_kitti_raw_calibration): the input holds the three files
// calib_cam_to_cam.txt, calib_velo_to_cam.txt and calib_imu_to_velo.txt in that order, separated by lines
// "#####" (a missing part is an empty file).
#include <array>

#include "fuzz/fuzz_input.hpp"
#include "io/kitti_raw.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const std::string kSeparator = "\n#####\n";
  std::array<std::string, 3> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i < parts.size() && start <= text.size(); ++i) {
    const std::size_t end = i + 1 < parts.size() ? text.find(kSeparator, start) : std::string::npos;
    parts[i] = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (end == std::string::npos) break;
    start = end + kSeparator.size();
  }
  fuzz::write_text("kitti_raw/calib_cam_to_cam.txt", parts[0]);
  fuzz::write_text("kitti_raw/calib_velo_to_cam.txt", parts[1]);
  fuzz::write_text("kitti_raw/calib_imu_to_velo.txt", parts[2]);
  fuzz::expect_clean_rejection(
      [&] { io::read_kitti_raw_calibration((fuzz::scratch_dir() / "kitti_raw").string()); });
  return 0;
}
