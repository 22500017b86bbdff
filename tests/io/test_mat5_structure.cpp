// check_mat5_structure: every array kind libmatio writes passes; layouts libmatio would read differently
// from the walk (parts beyond an array, a headless top-level array, elements between variables) are refused.
#include <matio.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/mat5_structure.hpp"
#include "io/mat_reader.hpp"
#include "support/test_data.hpp"

namespace glmbslam::io {
namespace {

using Bytes = std::vector<std::uint8_t>;

void put32(Bytes& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// A data element: tag, data, padding to 8 bytes.
Bytes element(std::uint32_t type, const Bytes& data) {
  Bytes out;
  put32(out, type);
  put32(out, static_cast<std::uint32_t>(data.size()));
  out.insert(out.end(), data.begin(), data.end());
  while (out.size() % 8 != 0) out.push_back(0);
  return out;
}

Bytes words(std::initializer_list<std::uint32_t> values) {
  Bytes out;
  for (std::uint32_t v : values) put32(out, v);
  return out;
}

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

/// An miMATRIX element of class `array_class` (flags word `flags`), dimensions 1 × `columns`, name "v",
/// then `parts`.
Bytes array(std::uint32_t flags, std::uint32_t nzmax, std::uint32_t columns, const Bytes& parts) {
  return element(14, concat({element(6, words({flags, nzmax})), element(5, words({1, columns})),
                             element(1, Bytes{'v'}), parts}));
}

Bytes doubles(std::size_t n) {
  return element(9, Bytes(8 * n, 0));
}

/// Writes a level-5 file: the 128-byte header (version 0x0100, little-endian), then `body`.
std::filesystem::path write_file(const std::string& name, const Bytes& body) {
  const auto path = test::fresh_temp_dir("mat5_structure") / name;
  Bytes bytes(116, ' ');
  bytes.resize(124, 0);
  bytes.insert(bytes.end(), {0x00, 0x01, 'I', 'M'});
  bytes.insert(bytes.end(), body.begin(), body.end());
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

std::string rejection(const std::filesystem::path& path) {
  try {
    check_mat5_structure(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(Mat5Structure, AcceptsAWellFormedArray) {
  EXPECT_NO_THROW(check_mat5_structure(write_file("ok.mat", array(6, 0, 3, doubles(3)))));
}

// Regression (fuzz_mat out-of-memory, CI): a top-level miMATRIX of 0 bytes was taken as an empty array and
// the bytes after its tag skipped as elements between variables; libmatio read them as the array's parts,
// one byte off, and allocated 5.9 GB from a dimension.
TEST(Mat5Structure, RefusesAHeadlessTopLevelArray) {
  const auto path = write_file("headless.mat", concat({element(14, {}), array(6, 0, 3, doubles(3))}));
  EXPECT_NE(rejection(path).find("an array is empty"), std::string::npos) << rejection(path);
}

TEST(Mat5Structure, RefusesAnElementBetweenVariables) {
  const auto path = write_file("between.mat", concat({doubles(1), array(6, 0, 3, doubles(3))}));
  EXPECT_NE(rejection(path).find("stands between the variables"), std::string::npos) << rejection(path);
}

TEST(Mat5Structure, RefusesDataBeyondAnArraysParts) {
  const auto path = write_file("beyond.mat", array(6, 0, 3, concat({doubles(3), doubles(1)})));
  EXPECT_NE(rejection(path).find("beyond its parts"), std::string::npos) << rejection(path);
}

TEST(Mat5Structure, RefusesDataThatDoesNotMatchTheDimensions) {
  EXPECT_NE(rejection(write_file("short.mat", array(6, 0, 3, doubles(2)))).find("stores 2 values for 3"),
            std::string::npos);
  EXPECT_NE(rejection(write_file("long.mat", array(6, 0, 3, doubles(4)))).find("stores 4 values for 3"),
            std::string::npos);
}

TEST(Mat5Structure, RefusesAComplexArrayWithoutItsImaginaryPart) {
  const auto path = write_file("complex.mat", array(6 | 0x0800, 0, 3, doubles(3)));
  EXPECT_NE(rejection(path).find("imaginary data"), std::string::npos) << rejection(path);
}

TEST(Mat5Structure, RefusesUnknownFlagBits) {
  const auto path = write_file("flags.mat", array(6 | 0x8000, 0, 3, doubles(3)));
  EXPECT_NE(rejection(path).find("unknown bits"), std::string::npos) << rejection(path);
}

// Regression (fuzz_mat out-of-memory, second CI-seed finding): a sparse array's parts ran past its end, so
// libmatio read the next variable's tag as column starts and allocated 4.3 GB.
TEST(Mat5Structure, RefusesASparseArrayMissingItsParts) {
  const Bytes rows = element(5, words({0, 1}));
  const Bytes starts = element(5, words({0, 1, 2}));
  EXPECT_NO_THROW(
      check_mat5_structure(write_file("sparse.mat", array(5, 2, 2, concat({rows, starts, doubles(2)})))));
  const auto cut =
      write_file("sparse_cut.mat", concat({array(5, 2, 2, doubles(2)), array(6, 0, 3, doubles(3))}));
  EXPECT_NE(rejection(cut).find("sparse"), std::string::npos) << rejection(cut);
  const auto wide = write_file("sparse_nzmax.mat", array(5, 9, 2, concat({rows, starts, doubles(2)})));
  EXPECT_NE(rejection(wide).find("non-zeros"), std::string::npos) << rejection(wide);
  // its data holds at most one value per row index, real and imaginary alike
  const auto more = write_file("sparse_data.mat", array(5, 2, 2, concat({rows, starts, doubles(3)})));
  EXPECT_NE(rejection(more).find("stores 3 values for at most 2"), std::string::npos) << rejection(more);
  const auto imaginary = write_file("sparse_imaginary.mat",
                                    array(5 | 0x0800, 2, 2, concat({rows, starts, doubles(2), doubles(3)})));
  EXPECT_NE(rejection(imaginary).find("imaginary data stores 3 values for at most 2"), std::string::npos)
      << rejection(imaginary);
  EXPECT_NO_THROW(check_mat5_structure(write_file(
      "sparse_complex.mat", array(5 | 0x0800, 2, 2, concat({rows, starts, doubles(2), doubles(1)})))));
}

// Every array kind libmatio writes (numeric, complex, char, logical, integer, sparse, cell, struct), plain
// and compressed, passes the walk and opens.
TEST(Mat5Structure, AcceptsEveryArrayKindLibmatioWrites) {
  for (const matio_compression compression : {MAT_COMPRESSION_NONE, MAT_COMPRESSION_ZLIB}) {
    const auto path = test::fresh_temp_dir("mat5_structure") /
                      (compression == MAT_COMPRESSION_NONE ? "kinds.mat" : "kinds_z.mat");
    mat_t* mat = Mat_CreateVer(path.string().c_str(), nullptr, MAT_FT_MAT5);
    ASSERT_NE(mat, nullptr);
    std::size_t dims[2] = {2, 3};
    double re[6] = {1, 2, 3, 4, 5, 6}, im[6] = {6, 5, 4, 3, 2, 1};
    mat_complex_split_t split{re, im};
    char text[6] = {'a', 'b', 'c', 'd', 'e', 'f'};
    std::uint8_t logical[6] = {1, 0, 1, 0, 1, 0};
    std::int32_t ints[6] = {-1, 2, -3, 4, -5, 6};
    std::vector<matvar_t*> vars = {
        Mat_VarCreate("real", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, re, 0),
        Mat_VarCreate("cplx", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, &split, MAT_F_COMPLEX),
        Mat_VarCreate("text", MAT_C_CHAR, MAT_T_UINT8, 2, dims, text, 0),
        Mat_VarCreate("flag", MAT_C_UINT8, MAT_T_UINT8, 2, dims, logical, MAT_F_LOGICAL),
        Mat_VarCreate("ints", MAT_C_INT32, MAT_T_INT32, 2, dims, ints, 0)};
    // sparse 2 × 3 with two non-zeros
    mat_uint32_t ir[2] = {0, 1}, jc[4] = {0, 1, 1, 2};
    double nz[2] = {7, 8};
    mat_sparse_t sparse{};
    sparse.nzmax = 2;
    sparse.ir = ir;
    sparse.nir = 2;
    sparse.jc = jc;
    sparse.njc = 4;
    sparse.ndata = 2;
    sparse.data = nz;
    vars.push_back(Mat_VarCreate("sprs", MAT_C_SPARSE, MAT_T_DOUBLE, 2, dims, &sparse, MAT_F_DONT_COPY_DATA));
    // a 1 × 2 cell: a matrix and an empty matrix
    std::size_t cell_dims[2] = {1, 2}, empty_dims[2] = {0, 0};
    matvar_t* cell = Mat_VarCreate("cell", MAT_C_CELL, MAT_T_CELL, 2, cell_dims, nullptr, 0);
    Mat_VarSetCell(cell, 0, Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, re, 0));
    Mat_VarSetCell(cell, 1, Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, empty_dims, nullptr, 0));
    vars.push_back(cell);
    // a 1 × 2 struct with fields x and name
    const char* fields[2] = {"x", "name"};
    matvar_t* st = Mat_VarCreateStruct("strc", 2, cell_dims, fields, 2);
    for (std::size_t i = 0; i < 2; ++i) {
      std::size_t one[2] = {1, 1}, word[2] = {1, 3};
      Mat_VarSetStructFieldByName(st, "x", i,
                                  Mat_VarCreate(nullptr, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, re + i, 0));
      Mat_VarSetStructFieldByName(st, "name", i,
                                  Mat_VarCreate(nullptr, MAT_C_CHAR, MAT_T_UINT8, 2, word, text + i, 0));
    }
    vars.push_back(st);
    for (matvar_t* v : vars) {
      ASSERT_NE(v, nullptr);
      EXPECT_EQ(Mat_VarWrite(mat, v, compression), 0) << v->name;
      Mat_VarFree(v);
    }
    Mat_Close(mat);
    EXPECT_NO_THROW(check_mat5_structure(path)) << rejection(path);
    const MatFile file(path);
    EXPECT_EQ(file.variable_names().size(), 8u);
    EXPECT_EQ(file.read_matrix("real", 2, 3)(1, 2), 6.0);
  }
}

}  // namespace
}  // namespace glmbslam::io
