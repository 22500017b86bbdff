// MatFile: typed reads with shape/class checks, and write_mat_file round trips.
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/mat5_structure.hpp"
#include "io/mat_reader.hpp"
#include "support/test_data.hpp"

namespace glmbslam::io {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MatReader, RoundTripMatrixVectorScalarCell) {
  const auto dir = test::fresh_temp_dir("mat_reader");
  const auto file = dir / "a.mat";
  Eigen::MatrixXd m(2, 3);
  m << 1, 2, 3, 4, 5, 6;
  std::vector<Eigen::MatrixXd> cells = {Eigen::MatrixXd::Constant(3, 2, 7.0), Eigen::MatrixXd(0, 0),
                                        Eigen::MatrixXd::Identity(3, 1)};
  write_mat_file(file, {MatVariable::matrix_variable("m", m),
                        MatVariable::matrix_variable("row", Eigen::RowVector3d(1, 2, 3)),
                        MatVariable::matrix_variable("col", Eigen::Vector2d(4, 5)),
                        MatVariable::matrix_variable("s", Eigen::MatrixXd::Constant(1, 1, 2.5)),
                        MatVariable::cell_variable("c", cells)});
  const MatFile f(file);
  EXPECT_TRUE(f.has("m"));
  EXPECT_FALSE(f.has("nope"));
  EXPECT_EQ(f.variable_names().size(), 5u);
  EXPECT_EQ(f.read_matrix("m", 2, 3), m);
  EXPECT_EQ(f.read_vector("row", 3), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(f.read_vector("col"), Eigen::Vector2d(4, 5));
  EXPECT_EQ(f.read_scalar("s"), 2.5);
  const auto c = f.read_cell_matrices("c", 3, 3);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0], cells[0]);
  EXPECT_EQ(c[1].rows(), 3);
  EXPECT_EQ(c[1].cols(), 0);
  EXPECT_EQ(c[2], cells[2]);
}

TEST(MatReader, ErrorsNameTheVariable) {
  const auto dir = test::fresh_temp_dir("mat_reader");
  const auto file = dir / "b.mat";
  Eigen::MatrixXd nan = Eigen::MatrixXd::Zero(2, 2);
  nan(1, 1) = std::numeric_limits<double>::quiet_NaN();
  write_mat_file(
      file, {MatVariable::matrix_variable("m", Eigen::MatrixXd::Zero(2, 3)),
             MatVariable::matrix_variable("bad", nan),
             MatVariable::cell_variable("c", {Eigen::MatrixXd::Zero(3, 2), Eigen::MatrixXd::Zero(2, 2)})});
  const MatFile f(file);
  EXPECT_NE(error_of([&] { f.read_matrix("missing"); }).find("'missing' is missing"), std::string::npos);
  EXPECT_NE(error_of([&] { f.read_matrix("m", 3, 3); }).find("'m' must be 3x3, found 2x3"),
            std::string::npos);
  EXPECT_NE(error_of([&] { f.read_vector("m"); }).find("'m' must be a vector"), std::string::npos);
  EXPECT_NE(error_of([&] { f.read_matrix("bad"); }).find("'bad' holds a NaN"), std::string::npos);
  EXPECT_NO_THROW(f.read_matrix("bad", 2, 2, /*require_finite=*/false));
  EXPECT_NE(error_of([&] { f.read_matrix("c"); }).find("'c' must be a numeric matrix, found class cell"),
            std::string::npos);
  EXPECT_NE(error_of([&] { f.read_cell_matrices("m"); }).find("'m' must be a cell array"), std::string::npos);
  EXPECT_NE(error_of([&] { f.read_cell_matrices("c", 3); }).find("'c{2}' must be 3xany, found 2x2"),
            std::string::npos);
  EXPECT_NE(error_of([&] { f.read_cell_matrices("c", io::kAnySize, 5); }).find("must have 5 cells"),
            std::string::npos);
  // The message starts with the file name.
  EXPECT_EQ(error_of([&] { f.read_matrix("missing"); }).rfind(file.string(), 0), 0u);
}

TEST(MatReader, RejectsMissingAndNonMatFiles) {
  const auto dir = test::fresh_temp_dir("mat_reader");
  EXPECT_THROW(MatFile(dir / "none.mat"), InputError);
  const auto text = dir / "text.mat";
  {
    std::ofstream out(text);
    out << "not a mat file\n";
  }
  EXPECT_THROW(MatFile{text}, InputError);
  // Regression (fuzz_mat out-of-memory, third finding): a level-4 header (no signature) whose name length
  // is 2^31 − 1 made libmatio's level-4 fallback allocate 2 GB; level-4 files are refused.
  const auto level4 = dir / "level4.mat";
  {
    const std::int32_t header[5] = {0, 1, 1, 0, 0x7FFFFFFF};  // type, rows, cols, imaginary, name length
    std::ofstream out(level4, std::ios::binary);
    out.write(reinterpret_cast<const char*>(header), sizeof(header));
    out << std::string(200, 'x');
  }
  EXPECT_NE(error_of([&] { MatFile f(level4); }).find("not a MATLAB level-5 or 7.3"), std::string::npos);
}

/// Writes a 1×2 double variable `name` to `file`, then sets the byte `offset` after the first occurrence of
/// `pattern` to `value`; returns the reader's error message for the damaged file.
std::string error_of_damaged(const std::filesystem::path& file, const std::string& name,
                             const std::string& pattern, std::size_t offset, char value) {
  Eigen::MatrixXd row(1, 2);
  row << -41.7, -41.6;
  write_mat_file(file, {MatVariable::matrix_variable(name, row)});
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto at = bytes.find(pattern);
  if (at == std::string::npos) return "pattern not found";
  bytes[at + offset] = value;
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  return error_of([&] { MatFile f(file); });
}

// Regression (fuzz_mat out-of-memory): a header declaring dims of billions made libmatio allocate tens of
// gigabytes before reading a byte. The check rejects it with a message naming the variable.
TEST(MatReader, RejectsAHeaderDeclaringMoreDataThanTheFileHolds) {
  const auto file = test::fresh_temp_dir("mat_reader") / "huge_dims.mat";
  // MAT5 dimensions sub-element: miINT32 tag (type 5, 8 bytes), then dims 1 and 2; the second becomes
  // 0x55000002 ≈ 1.4e9 columns ≈ 11 GB of doubles
  const std::string message =
      error_of_damaged(file, "La_m", std::string("\x05\0\0\0\x08\0\0\0\x01\0\0\0\x02\0\0\0", 16), 15, '\x55');
  EXPECT_NE(message.find("'La_m'"), std::string::npos) << message;
  EXPECT_NE(message.find("corrupt or truncated"), std::string::npos) << message;
}

// Regression (fuzz_mat out-of-memory, second finding): a dimensions tag declaring 65 544 bytes inside a
// 72-byte array made libmatio's header read allocate 2.6 GB. The structural check rejects any element larger
// than what contains it.
TEST(MatReader, RejectsAnElementTagLargerThanItsArray) {
  const auto file = test::fresh_temp_dir("mat_reader") / "huge_tag.mat";
  // the dimensions tag's size 8 → 65 544 bytes
  const std::string message =
      error_of_damaged(file, "Lo_m", std::string("\x05\0\0\0\x08\0\0\0", 8), 6, '\x01');
  EXPECT_NE(message.find("corrupt or truncated"), std::string::npos) << message;
  EXPECT_EQ(message.rfind(file.string(), 0), 0u) << message;
}

// Regression (fuzz_mat out-of-memory, fourth finding): an array of unknown class 42 with dims of 10^7 made
// libmatio allocate 1.8 GB while reading the headers.
TEST(MatReader, RejectsAnArrayOfUnknownClass) {
  const auto file = test::fresh_temp_dir("mat_reader") / "bad_class.mat";
  // array flags: miUINT32 tag (type 6, 8 bytes), then the class byte (6 = double) → 42
  const std::string message =
      error_of_damaged(file, "timeGps", std::string("\x06\0\0\0\x08\0\0\0\x06", 9), 8, '\x2a');
  EXPECT_NE(message.find("unknown class 42"), std::string::npos) << message;
}

// Every input the .mat fuzzer found (out-of-memory in libmatio, a heap overflow in the header pass, arrays
// whose parts libmatio read from the next variable; the first byte of the fuzzer's input, which picks the
// file, removed) is a clean InputError, whatever is read.
TEST(MatReader, FuzzFindingsAreCleanRejections) {
  const std::filesystem::path dir = std::filesystem::path(GLMBSLAM_SOURCE_DIR) / "tests/io/mat_fuzz_findings";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    ++files;
    // each is refused by the structural walk, before libmatio allocates from what it declares
    EXPECT_THROW(check_mat5_structure(entry.path()), InputError) << entry.path();
    try {
      const MatFile f(entry.path());
      for (const auto& name : f.variable_names()) {
        try {
          f.read_matrix(name);
        } catch (const InputError&) {
          f.read_cell_matrices(name);
        }
      }
    } catch (const InputError&) {
      continue;  // rejected with a message naming the file: what is expected
    }
  }
  EXPECT_GE(files, 7);
}

// The structural check accepts what write_mat_file writes and the shared files (compressed and not).
TEST(MatReader, StructureCheckAcceptsValidFiles) {
  const auto dir = test::fresh_temp_dir("mat_reader");
  const auto file = dir / "cells.mat";
  write_mat_file(file,
                 {MatVariable::matrix_variable("m", Eigen::MatrixXd::Identity(3, 4)),
                  MatVariable::cell_variable("c", {Eigen::MatrixXd::Ones(3, 2), Eigen::MatrixXd(0, 0)})});
  EXPECT_NO_THROW(check_mat5_structure(file));
  const auto root = test::shared_data_dir();
  for (const char* name :
       {"victoria_park/aa3_dr.mat", "victoria_park/aa3_gpsx.mat",
        "victoria_park/VictoriaParkSinSincronizar.mat", "phdslam3_synthetic/Environment_SLAM.mat",
        "phdslam3_synthetic/Robot_Measurement.mat"}) {
    if (std::filesystem::exists(root / name)) {
      EXPECT_NO_THROW(check_mat5_structure(root / name)) << name;
    }
  }
}

TEST(MatReader, ReadsTheSharedBenchmarkFile) {
  GLMBSLAM_REQUIRE_DATA(path, "phdslam3_synthetic/Environment_SLAM.mat");
  const MatFile f(path);
  const Eigen::MatrixXd gt = f.read_matrix("Robot_Groundtruth", 3, 4000);
  EXPECT_DOUBLE_EQ(gt(0, 0), 300.0);
  EXPECT_DOUBLE_EQ(gt(1, 0), 400.0);
  EXPECT_NEAR(gt(2, 0), -5.0 * M_PI / 180.0, 1e-9);
}

}  // namespace
}  // namespace glmbslam::io
