// KITTI odometry times.txt (one time in seconds a line): io::read_kitti_times.
#include "fuzz/fuzz_input.hpp"
#include "io/kitti_odometry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string path = fuzz::write_input("times.txt", data, size);
  fuzz::expect_clean_rejection([&] { io::read_kitti_times(path); });
  return 0;
}
