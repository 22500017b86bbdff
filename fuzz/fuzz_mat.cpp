// The .mat reader (libmatio through io::MatFile) as the datasets use it: the first byte picks the file the
// rest of the input replaces —
//   0-2  one of the three Victoria Park files (io::read_victoria_park; the other two are small valid files),
//   3    the phdslam3 environment (sim::load_phdslam3_environment).
#include <Eigen/Core>

#include "fuzz/fuzz_input.hpp"
#include "io/mat_reader.hpp"
#include "io/victoria_park.hpp"
#include "sim/scenario_phdslam3.hpp"

namespace {

using glmbslam::io::MatVariable;

Eigen::MatrixXd row(std::initializer_list<double> values) {
  Eigen::MatrixXd m(1, static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double v : values) m(0, i++) = v;
  return m;
}

/// Writes the three small valid Victoria Park files into `dir` (once per process).
void write_valid_victoria_park(const std::filesystem::path& dir) {
  using glmbslam::io::write_mat_file;
  std::filesystem::create_directories(dir);
  write_mat_file(dir / glmbslam::io::kVictoriaParkOdometryFile,
                 {MatVariable::matrix_variable("speed", row({1.0, 1.1, 1.2, 1.2})),
                  MatVariable::matrix_variable("steering", row({0.0, 0.01, 0.02, 0.0})),
                  MatVariable::matrix_variable("time", row({0.0, 25.0, 50.0, 75.0}))});
  write_mat_file(dir / glmbslam::io::kVictoriaParkGpsFile,
                 {MatVariable::matrix_variable("timeGps", row({0.0, 50.0})),
                  MatVariable::matrix_variable("Lo_m", row({-67.6, -67.5})),
                  MatVariable::matrix_variable("La_m", row({-41.7, -41.6}))});
  Eigen::MatrixXd z(3, 2);
  z << 10.0, 12.0, 1.2, 1.9, 0.3, 0.4;
  write_mat_file(dir / glmbslam::io::kVictoriaParkDetectionsFile,
                 {MatVariable::matrix_variable("TLsr", row({0.01, 0.06})),
                  MatVariable::cell_variable("zt", {z, Eigen::MatrixXd(3, 0)})});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  if (size == 0) return 0;
  const int which = data[0] % 4;
  if (which == 3) {
    const std::string path = fuzz::write_input("Environment_SLAM.mat", data + 1, size - 1);
    fuzz::expect_clean_rejection([&] { sim::load_phdslam3_environment(path); });
    return 0;
  }
  const std::filesystem::path dir = fuzz::scratch_dir() / "victoria_park";
  static const bool written = (write_valid_victoria_park(dir), true);
  (void)written;
  static const char* const kFiles[] = {io::kVictoriaParkOdometryFile, io::kVictoriaParkGpsFile,
                                       io::kVictoriaParkDetectionsFile};
  const std::filesystem::path target = dir / kFiles[which];
  const std::filesystem::path saved = dir / "saved.mat";
  std::filesystem::copy_file(target, saved, std::filesystem::copy_options::overwrite_existing);
  fuzz::write_input(std::string("victoria_park/") + kFiles[which], data + 1, size - 1);
  fuzz::expect_clean_rejection([&] { io::read_victoria_park(dir); });
  std::filesystem::rename(saved, target);
  return 0;
}
