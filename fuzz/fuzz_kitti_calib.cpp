// KITTI odometry calib.txt (P0..P3, Tr): io::read_kitti_odometry_calibration.
#include "fuzz/fuzz_input.hpp"
#include "io/kitti_odometry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string path = fuzz::write_input("calib.txt", data, size);
  fuzz::expect_clean_rejection([&] { io::read_kitti_odometry_calibration(path); });
  return 0;
}
