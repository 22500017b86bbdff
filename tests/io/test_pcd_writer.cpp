#include "io/pcd_writer.hpp"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "support/test_data.hpp"
#include "tests/io/fake_kitti.hpp"

namespace glmbslam::io {
namespace {

using test::expect_input_error;
namespace fs = std::filesystem;

std::vector<MapPoint> sample_map() {
  std::vector<MapPoint> m;
  for (int i = 0; i < 50; ++i) {
    MapPoint p;
    p.position = Eigen::Vector3d(0.25 * i - 3.0, -1.5 + 0.125 * i, 10.0 + 2.0 * i);
    p.label = static_cast<std::uint64_t>(1000 * i + 7);
    p.existence = i / 49.0;
    m.push_back(p);
  }
  m.back().label = 4294967295u;  // largest label that fits
  return m;
}

std::string header_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  std::string header;
  while (std::getline(in, line)) {
    header += line + "\n";
    if (line.rfind("DATA", 0) == 0) break;
  }
  return header;
}

void expect_same(const std::vector<MapPoint>& a, const std::vector<MapPoint>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    // Positions are stored as float32: relative precision 2^-24.
    EXPECT_LT((a[i].position - b[i].position).norm(), 1e-6 * (1.0 + a[i].position.norm())) << i;
    EXPECT_EQ(a[i].label, b[i].label) << i;
    EXPECT_NEAR(a[i].existence, b[i].existence, 1e-7) << i;
  }
}

TEST(PcdWriter, BinaryRoundTrip) {
  const auto dir = test::fresh_temp_dir("pcd");
  const auto file = dir / "map.pcd";
  const auto map = sample_map();
  write_pcd_map(file.string(), map);
  const std::string header = header_of(file);
  EXPECT_NE(header.find("FIELDS x y z label existence"), std::string::npos) << header;
  EXPECT_NE(header.find("TYPE F F F U F"), std::string::npos) << header;
  EXPECT_NE(header.find("POINTS 50"), std::string::npos) << header;
  EXPECT_NE(header.find("DATA binary"), std::string::npos) << header;
  expect_same(map, read_pcd_map(file.string()));
  // Only the final file remains (no temporary left behind).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(PcdWriter, AsciiRoundTrip) {
  const auto dir = test::fresh_temp_dir("pcd");
  const auto file = dir / "map.pcd";
  const auto map = sample_map();
  write_pcd_map(file.string(), map, /*binary=*/false);
  EXPECT_NE(header_of(file).find("DATA ascii"), std::string::npos);
  expect_same(map, read_pcd_map(file.string()));
  // The ASCII body: one line per point with 5 values, the label as an integer.
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line) && line.rfind("DATA", 0) != 0) {
  }
  std::getline(in, line);
  std::istringstream ss(line);
  double x, y, z, e;
  unsigned long label;
  ASSERT_TRUE(ss >> x >> y >> z >> label >> e) << line;
  EXPECT_NEAR(x, -3.0, 1e-6);
  EXPECT_EQ(label, 7u);
}

TEST(PcdWriter, EmptyMapIsAValidFile) {
  const auto dir = test::fresh_temp_dir("pcd");
  const auto file = dir / "empty.pcd";
  write_pcd_map(file.string(), {});
  EXPECT_TRUE(read_pcd_map(file.string()).empty());
  EXPECT_NE(header_of(file).find("POINTS 0"), std::string::npos);
}

TEST(PcdWriter, OverwritesExistingFile) {
  const auto dir = test::fresh_temp_dir("pcd");
  const auto file = dir / "map.pcd";
  write_pcd_map(file.string(), sample_map());
  std::vector<MapPoint> one(1);
  one[0].position = Eigen::Vector3d(1, 2, 3);
  one[0].label = 9;
  one[0].existence = 0.5;
  write_pcd_map(file.string(), one);
  expect_same(one, read_pcd_map(file.string()));
}

TEST(PcdWriter, RejectsBadPoints) {
  const auto dir = test::fresh_temp_dir("pcd");
  const auto file = dir / "map.pcd";
  std::vector<MapPoint> m(2);
  m[1].position.x() = std::numeric_limits<double>::quiet_NaN();
  expect_input_error([&] { write_pcd_map(file.string(), m); }, "map.pcd", "non-finite position");
  m[1].position.x() = 0.0;
  m[1].existence = 1.5;
  expect_input_error([&] { write_pcd_map(file.string(), m); }, "map.pcd", "existence outside [0, 1]");
  m[1].existence = 1.0;
  m[1].label = 1ull << 32;
  expect_input_error([&] { write_pcd_map(file.string(), m); }, "map.pcd", "exceeds 32 bits");
  EXPECT_FALSE(fs::exists(file));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  expect_input_error([&] { write_pcd_map((dir / "no_such_dir" / "m.pcd").string(), {MapPoint{}}); }, "m.pcd",
                     "cannot write");
}

TEST(PcdWriter, ReaderErrors) {
  const auto dir = test::fresh_temp_dir("pcd");
  expect_input_error([&] { read_pcd_map((dir / "none.pcd").string()); }, "none.pcd", "not found");
  test::write_text(dir / "junk.pcd", "this is not a pcd file\n");
  expect_input_error([&] { read_pcd_map((dir / "junk.pcd").string()); }, "junk.pcd", "unreadable");
  test::write_text(dir / "xyz.pcd",
                   "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
                   "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n");
  expect_input_error([&] { read_pcd_map((dir / "xyz.pcd").string()); }, "xyz.pcd", "'label'");
  // A binary file cut short.
  write_pcd_map((dir / "cut.pcd").string(), sample_map());
  fs::resize_file(dir / "cut.pcd", header_of(dir / "cut.pcd").size() + 500);  // 25 of the 50 points
  expect_input_error([&] { read_pcd_map((dir / "cut.pcd").string()); }, "cut.pcd", "PCD");
}

}  // namespace
}  // namespace glmbslam::io
