#include "io/euroc_files.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>
#include <Eigen/SVD>

#include "core/error.hpp"
#include "io/kitti_common.hpp"

namespace glmbslam::io {

using detail::file_line;

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ',')) out.push_back(trim(field));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

bool parse_int64(const std::string& text, std::int64_t& out) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (errno == ERANGE || *end != '\0') return false;
  out = v;
  return true;
}

bool parse_double(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return *end == '\0' && std::isfinite(out);
}

/// Calls `row(fields, line_number)` for every line that is neither blank nor a '#' comment.
template <typename RowFn>
void for_each_csv_row(const std::string& path, const std::string& what, RowFn row) {
  detail::require_file(path, what);
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open " + what);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    row(split_csv(t), n);
  }
  if (in.bad()) throw InputError(path, "read error");
}

void require_increasing(std::int64_t previous, std::int64_t t, bool first, const std::string& path,
                        std::size_t n) {
  if (!first && t <= previous) throw InputError(file_line(path, n), "timestamps are not strictly increasing");
}

/// The sequence `key` of numbers, of `count` elements (0: any non-empty count).
std::vector<double> yaml_numbers(const YAML::Node& root, const std::string& key, std::size_t count,
                                 const std::string& path) {
  const YAML::Node node = root[key];
  if (!node) throw InputError(path, "missing key '" + key + "'");
  if (!node.IsSequence()) throw InputError(path, "'" + key + "' is not a list");
  std::vector<double> out;
  for (const auto& item : node) {
    double v = 0.0;
    if (!item.IsScalar() || !parse_double(item.Scalar(), v))
      throw InputError(path, "'" + key + "' holds a value that is not a finite number");
    out.push_back(v);
  }
  if (count > 0 ? out.size() != count : out.empty()) {
    throw InputError(path, "'" + key + "' has " + std::to_string(out.size()) + " values, expected " +
                               (count > 0 ? std::to_string(count) : std::string("at least one")));
  }
  return out;
}

std::string yaml_string(const YAML::Node& root, const std::string& key, const std::string& path) {
  const YAML::Node node = root[key];
  if (!node || !node.IsScalar()) throw InputError(path, "missing key '" + key + "'");
  return node.Scalar();
}

}  // namespace

std::vector<EurocImageEntry> read_euroc_camera_csv(const std::string& path) {
  std::vector<EurocImageEntry> entries;
  for_each_csv_row(path, "camera data.csv", [&](const std::vector<std::string>& f, std::size_t n) {
    if (f.size() != 2) throw InputError(file_line(path, n), "expected 'timestamp_ns,filename'");
    EurocImageEntry e;
    if (!parse_int64(f[0], e.timestamp_ns))
      throw InputError(file_line(path, n), "timestamp '" + f[0] + "' is not a non-negative integer");
    if (f[1].empty() || f[1].find('/') != std::string::npos || f[1] == "." || f[1] == "..")
      throw InputError(file_line(path, n), "bad image file name '" + f[1] + "'");
    require_increasing(entries.empty() ? 0 : entries.back().timestamp_ns, e.timestamp_ns, entries.empty(),
                       path, n);
    e.filename = f[1];
    entries.push_back(std::move(e));
  });
  if (entries.empty()) throw InputError(path, "lists no image");
  return entries;
}

EurocCameraSensor read_euroc_sensor_yaml(const std::string& path) {
  detail::require_file(path, "sensor.yaml");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open sensor.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string content = text.str();
  // OpenCV-style "%YAML:1.0" directive: not YAML 1.2 syntax, dropped before parsing.
  if (content.rfind("%YAML:", 0) == 0) content.erase(0, content.find('\n'));
  YAML::Node root;
  try {
    root = YAML::Load(content);
  } catch (const YAML::Exception& e) {
    throw InputError(path, std::string("not valid YAML: ") + e.what());
  }
  if (!root.IsMap()) throw InputError(path, "is not a YAML mapping");
  EurocCameraSensor s;
  const YAML::Node tbs = root["T_BS"];
  if (!tbs || !tbs.IsMap()) throw InputError(path, "missing key 'T_BS'");
  const std::vector<double> m = yaml_numbers(tbs, "data", 16, path + " T_BS");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = m[static_cast<std::size_t>(4 * r + c)];
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
      R.determinant() <= 0.0 || (M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
    throw InputError(path, "T_BS is not a rigid transform");
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  s.T_BS.linear() = svd.matrixU() * svd.matrixV().transpose();
  s.T_BS.translation() = M.topRightCorner<3, 1>();

  const std::string model = yaml_string(root, "camera_model", path);
  if (model != "pinhole") throw InputError(path, "camera_model '" + model + "' is not supported (pinhole)");
  const std::string dmodel = yaml_string(root, "distortion_model", path);
  if (dmodel != "radial-tangential" && dmodel != "radtan")
    throw InputError(path, "distortion_model '" + dmodel + "' is not supported (radial-tangential)");
  const std::vector<double> k = yaml_numbers(root, "intrinsics", 4, path);
  s.fu = k[0];
  s.fv = k[1];
  s.cu = k[2];
  s.cv = k[3];
  if (!(s.fu > 0.0) || !(s.fv > 0.0)) throw InputError(path, "intrinsics: focal lengths must be positive");
  s.distortion = yaml_numbers(root, "distortion_coefficients", 0, path);
  if (s.distortion.size() != 4 && s.distortion.size() != 5)
    throw InputError(path, "distortion_coefficients must hold 4 or 5 values (k1 k2 p1 p2 [k3])");
  const std::vector<double> res = yaml_numbers(root, "resolution", 2, path);
  if (!(res[0] >= 1 && res[0] <= 65536 && res[1] >= 1 && res[1] <= 65536) || res[0] != std::floor(res[0]) ||
      res[1] != std::floor(res[1]))
    throw InputError(path, "resolution must be two positive integers");
  s.width = static_cast<int>(res[0]);
  s.height = static_cast<int>(res[1]);
  if (!(s.cu >= 0.0 && s.cu < s.width && s.cv >= 0.0 && s.cv < s.height))
    throw InputError(path, "principal point lies outside the image");
  if (root["rate_hz"]) {
    if (!root["rate_hz"].IsScalar() || !parse_double(root["rate_hz"].Scalar(), s.rate_hz) || s.rate_hz < 0.0)
      throw InputError(path, "rate_hz is not a non-negative number");
  }
  return s;
}

std::vector<EurocGroundTruthRecord> read_euroc_groundtruth_csv(const std::string& path) {
  std::vector<EurocGroundTruthRecord> records;
  for_each_csv_row(path, "ground-truth data.csv", [&](const std::vector<std::string>& f, std::size_t n) {
    if (f.size() < 8) {
      throw InputError(file_line(path, n), "has " + std::to_string(f.size()) +
                                               " columns, expected at least 8 (timestamp, p xyz, q wxyz)");
    }
    EurocGroundTruthRecord r;
    if (!parse_int64(f[0], r.timestamp_ns))
      throw InputError(file_line(path, n), "timestamp '" + f[0] + "' is not a non-negative integer");
    double v[7];
    for (int i = 0; i < 7; ++i) {
      if (!parse_double(f[static_cast<std::size_t>(i + 1)], v[i]))
        throw InputError(file_line(path, n), "column " + std::to_string(i + 2) + " is not a finite number");
    }
    Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (!(q.norm() > 1e-6)) throw InputError(file_line(path, n), "quaternion has zero norm");
    q.normalize();
    r.T_WB.linear() = q.toRotationMatrix();
    r.T_WB.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    require_increasing(records.empty() ? 0 : records.back().timestamp_ns, r.timestamp_ns, records.empty(),
                       path, n);
    records.push_back(r);
  });
  if (records.empty()) throw InputError(path, "holds no ground-truth record");
  return records;
}

}  // namespace glmbslam::io
