// EuRoC ASL files: the first byte picks the parser (cam0/data.csv, cam0/sensor.yaml or
// state_groundtruth_estimate0/data.csv), the rest is the file.
#include "fuzz/fuzz_input.hpp"
#include "io/euroc_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  if (size == 0) return 0;
  const int which = data[0] % 3;
  const std::string path = fuzz::write_input("euroc_file", data + 1, size - 1);
  fuzz::expect_clean_rejection([&] {
    if (which == 0) io::read_euroc_camera_csv(path);
    if (which == 1) io::read_euroc_sensor_yaml(path);
    if (which == 2) io::read_euroc_groundtruth_csv(path);
  });
  return 0;
}
