// KITTI pose files (poses/XX.txt, trajectory.txt): io::read_kitti_poses.
#include "fuzz/fuzz_input.hpp"
#include "io/trajectory_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string path = fuzz::write_input("poses.txt", data, size);
  fuzz::expect_clean_rejection([&] { io::read_kitti_poses(path); });
  return 0;
}
