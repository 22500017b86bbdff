// TUM trajectories (timestamp tx ty tz qx qy qz qw): io::read_tum_trajectory.
#include "fuzz/fuzz_input.hpp"
#include "io/trajectory_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string path = fuzz::write_input("trajectory.tum", data, size);
  fuzz::expect_clean_rejection([&] { io::read_tum_trajectory(path); });
  return 0;
}
