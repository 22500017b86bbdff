// The only translation unit that includes PCL headers (they are slow to compile).
#include "io/pcd_writer.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace glmbslam::io {

namespace {

constexpr std::uint32_t kPointStep = 20;  // x y z label existence, 4 bytes each

pcl::PCLPointField make_field(const std::string& name, std::uint32_t offset, std::uint8_t datatype) {
  pcl::PCLPointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = datatype;
  f.count = 1;
  return f;
}

int field_index(const pcl::PCLPointCloud2& cloud, const std::string& name) {
  for (std::size_t i = 0; i < cloud.fields.size(); ++i) {
    if (cloud.fields[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

/// Reads field `index` of point `i` as a double (any numeric PCD datatype).
double read_field(const pcl::PCLPointCloud2& cloud, int index, std::size_t i) {
  const auto& f = cloud.fields[static_cast<std::size_t>(index)];
  const std::uint8_t* p = cloud.data.data() + i * cloud.point_step + f.offset;
  switch (f.datatype) {
    case pcl::PCLPointField::INT8: {
      std::int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case pcl::PCLPointField::UINT8: {
      std::uint8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case pcl::PCLPointField::INT16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::UINT16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::INT32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::UINT32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    default:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

void write_pcd_map(const std::string& path, const std::vector<MapPoint>& points, bool binary) {
  pcl::PCLPointCloud2 cloud;
  cloud.fields = {
      make_field("x", 0, pcl::PCLPointField::FLOAT32), make_field("y", 4, pcl::PCLPointField::FLOAT32),
      make_field("z", 8, pcl::PCLPointField::FLOAT32), make_field("label", 12, pcl::PCLPointField::UINT32),
      make_field("existence", 16, pcl::PCLPointField::FLOAT32)};
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(points.size());
  cloud.point_step = kPointStep;
  cloud.row_step = kPointStep * cloud.width;
  cloud.is_dense = true;
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const MapPoint& m = points[i];
    if (!m.position.allFinite()) {
      throw InputError(path,
                       "cannot write map: landmark " + std::to_string(i) + " has a non-finite position");
    }
    if (!(m.existence >= 0.0 && m.existence <= 1.0)) {
      throw InputError(path,
                       "cannot write map: landmark " + std::to_string(i) + " has existence outside [0, 1]");
    }
    if (m.label > std::numeric_limits<std::uint32_t>::max()) {
      throw InputError(path,
                       "cannot write map: landmark label " + std::to_string(m.label) + " exceeds 32 bits");
    }
    const float xyz[3] = {static_cast<float>(m.position.x()), static_cast<float>(m.position.y()),
                          static_cast<float>(m.position.z())};
    const std::uint32_t label = static_cast<std::uint32_t>(m.label);
    const float existence = static_cast<float>(m.existence);
    std::uint8_t* dst = cloud.data.data() + i * kPointStep;
    std::memcpy(dst, xyz, 12);
    std::memcpy(dst + 12, &label, 4);
    std::memcpy(dst + 16, &existence, 4);
  }

  const auto tmp = temporary_path_for(path);
  int rc = -1;
  try {
    if (points.empty()) {
      // PCL refuses to write a cloud without points; its header is written by hand (the format allows 0
      // points).
      write_text_file_atomically(tmp, [](std::ostream& out) {
        out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z label existence\n"
               "SIZE 4 4 4 4 4\nTYPE F F F U F\nCOUNT 1 1 1 1 1\nWIDTH 0\nHEIGHT 1\n"
               "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n";
      });
      rc = 0;
    } else {
      pcl::PCDWriter writer;
      rc = writer.write(tmp.string(), cloud, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), binary);
    }
  } catch (const pcl::PCLException& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw InputError(path, std::string("cannot write PCD map (") + e.what() + ")");
  }
  if (rc != 0) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw InputError(path, "cannot write PCD map");
  }
  commit_temporary(tmp, path);
}

std::vector<MapPoint> read_pcd_map(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "PCD map not found");
  pcl::PCLPointCloud2 cloud;
  try {
    pcl::PCDReader reader;
    // The header is checked first: PCDReader::read crashes on a file without a FIELDS line.
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0;
    int data_type = 0;
    unsigned int data_index = 0;
    if (reader.readHeader(path, cloud, origin, orientation, version, data_type, data_index) < 0) {
      throw InputError(path, "unreadable PCD file (bad header)");
    }
    if (cloud.fields.empty() || cloud.point_step == 0)
      throw InputError(path, "unreadable PCD file (no FIELDS)");
    const std::size_t declared = static_cast<std::size_t>(cloud.width) * cloud.height;
    if (data_type == 1 && std::filesystem::file_size(path, ec) < data_index + declared * cloud.point_step) {
      throw InputError(path, "PCD data is shorter than its header says (file truncated?)");
    }
    if (declared > 0 && reader.read(path, cloud) < 0) {
      throw InputError(path, "unreadable PCD file");
    }
  } catch (const pcl::PCLException& e) {
    throw InputError(path, std::string("unreadable PCD file (") + e.what() + ")");
  }
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  std::vector<MapPoint> out;
  const int ix = field_index(cloud, "x");
  const int il = field_index(cloud, "label");
  const int ie = field_index(cloud, "existence");
  if (ix < 0 || field_index(cloud, "y") < 0 || field_index(cloud, "z") < 0) {
    throw InputError(path, "PCD file lacks an x, y or z field");
  }
  if (il < 0) throw InputError(path, "PCD file lacks the 'label' field");
  if (ie < 0) throw InputError(path, "PCD file lacks the 'existence' field");
  if (n == 0) return out;
  if (cloud.data.size() < n * cloud.point_step)
    throw InputError(path, "PCD data is shorter than its header says");
  // Positions through pcl::fromPCLPointCloud2 into PointXYZ, exactly as pcl_viewer reads them.
  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::fromPCLPointCloud2(cloud, xyz);
  if (xyz.size() != n) throw InputError(path, "PCD point count does not match its width and height");
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i].position = xyz[i].getVector3fMap().cast<double>();
    const double label = read_field(cloud, il, i);
    if (!(label >= 0.0) || label != std::floor(label)) {
      throw InputError(path, "point " + std::to_string(i) + " has an invalid label");
    }
    out[i].label = static_cast<std::uint64_t>(label);
    out[i].existence = read_field(cloud, ie, i);
  }
  return out;
}

}  // namespace glmbslam::io
