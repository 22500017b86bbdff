// KITTI raw oxts records (30 values a line): io::read_oxts_file.
#include "fuzz/fuzz_input.hpp"
#include "io/oxts.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string path = fuzz::write_input("oxts.txt", data, size);
  fuzz::expect_clean_rejection([&] { io::read_oxts_file(path); });
  return 0;
}
