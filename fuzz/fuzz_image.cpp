// Image decoding of a frame (PNG, or anything OpenCV recognises), with and without the expected size:
// io::detail::read_gray_image.
#include "fuzz/fuzz_input.hpp"
#include "io/kitti_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string path = fuzz::write_input("frame.png", data, size);
  fuzz::expect_clean_rejection([&] { io::detail::read_gray_image(path); });
  fuzz::expect_clean_rejection([&] { io::detail::read_gray_image(path, 16, 8); });
  return 0;
}
