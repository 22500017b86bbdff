#include "io/kitti_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>
#include <system_error>

#include <spdlog/spdlog.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.hpp"

namespace glmbslam::io::detail {

namespace fs = std::filesystem;

std::string file_line(const std::string& path, std::size_t line) {
  return path + ":" + std::to_string(line);
}

bool parse_number_list(const std::string& text, std::vector<double>& out) {
  out.clear();
  std::istringstream ss(text);
  std::string tok;
  while (ss >> tok) {
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') return false;
    out.push_back(v);
  }
  return true;
}

bool is_blank_line(const std::string& line) {
  return line.find_first_not_of(" \t\r") == std::string::npos;
}

cv::Mat read_stereo_image(const std::string& name, std::size_t i, const ImageFileList& files, int width,
                          int height) {
  if (i >= files.size()) {
    throw InputError(
        name, "frame " + std::to_string(i) + " out of range (" + std::to_string(files.size()) + " frames)");
  }
  return read_gray_image(files.path(i), width, height);
}

void require_directory(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw InputError(dir.string(), what + " not found");
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string(), what + " is not a folder");
}

void require_file(const fs::path& file, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file.string(), what + " not found");
  if (!fs::is_regular_file(file, ec)) throw InputError(file.string(), what + " is not a regular file");
}

ImageFileList list_png_files(const fs::path& dir) {
  require_directory(dir, "image folder");
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.path().extension() == ".png") names.push_back(entry.path().filename().string());
  }
  if (ec) throw InputError(dir.string(), "cannot list image folder (" + ec.message() + ")");
  if (names.empty()) throw InputError(dir.string(), "image folder contains no .png image");
  std::sort(names.begin(), names.end());
  ImageFileList files(dir);
  for (auto& n : names) files.push_back(std::move(n));
  return files;
}

void require_stereo_pairs(const fs::path& dir, const ImageFileList& left, const ImageFileList& right) {
  // both lists are sorted by name: walk them together to the first name that only one of them has
  std::size_t i = 0, j = 0;
  while (i < left.size() && j < right.size() && left.name(i) == right.name(j)) ++i, ++j;
  if (i == left.size() && j == right.size()) return;
  const bool left_alone = j == right.size() || (i < left.size() && left.name(i) < right.name(j));
  const ImageFileList& has = left_alone ? left : right;
  const ImageFileList& lacks = left_alone ? right : left;
  const std::size_t k = left_alone ? i : j;
  throw InputError(
      has.path(k).string(),
      std::string(left_alone ? "left" : "right") + " image has no partner " +
          (lacks.folder() / has.name(k)).string() + " (" + left.folder().lexically_relative(dir).string() +
          " has " + std::to_string(left.size()) + " images, " +
          right.folder().lexically_relative(dir).string() + " has " + std::to_string(right.size()) + ")");
}

cv::Mat gray16_to_8bit(const cv::Mat& image) {
  double max_value = 0.0;
  cv::minMaxLoc(image, nullptr, &max_value);
  int bits = 8;
  while (bits < 16 && max_value >= static_cast<double>(1 << bits)) ++bits;
  cv::Mat out;
  image.convertTo(out, CV_8U, 255.0 / static_cast<double>((1 << bits) - 1));
  return out;
}

cv::Mat read_gray_image(const fs::path& file, int width, int height) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InputError(file.string(), "image is missing");
  cv::Mat img = cv::imread(file.string(), cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  if (img.empty()) throw InputError(file.string(), "image is unreadable (not a valid image file)");
  if (img.depth() == CV_16U) {
    static std::once_flag logged;
    std::call_once(logged, [&] {
      spdlog::info("{}: 16-bit image; scaled to 8 bits by the bit depth its values use (every 16-bit image)",
                   file.string());
    });
    img = gray16_to_8bit(img);
  } else if (img.depth() != CV_8U) {
    throw InputError(file.string(),
                     "image has an unsupported pixel depth (8- or 16-bit grey or colour expected)");
  }
  if (width > 0 && (img.cols != width || img.rows != height)) {
    throw InputError(file.string(), "image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                                        ", expected " + std::to_string(width) + "x" + std::to_string(height) +
                                        " like the first image of the sequence");
  }
  return img;
}

void fit_calibration_to_image(StereoCalibration& calib, const cv::Mat& first_image,
                              const std::string& calib_path, const std::string& image_path) {
  calib.width = first_image.cols;
  calib.height = first_image.rows;
  if (!(calib.cx > 0.0 && calib.cx < calib.width && calib.cy > 0.0 && calib.cy < calib.height)) {
    throw InputError(calib_path, "principal point (" + std::to_string(calib.cx) + ", " +
                                     std::to_string(calib.cy) + ") lies outside the " +
                                     std::to_string(calib.width) + "x" + std::to_string(calib.height) +
                                     " images (" + image_path +
                                     "): the calibration does not belong to these images");
  }
}

KeyValueFile::KeyValueFile(const std::string& path) : path_(path) {
  require_file(path, "calibration file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open calibration file");
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (is_blank_line(line)) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) {
      throw InputError(file_line(path, n), "calibration line has no 'key:' prefix");
    }
    std::string key = line.substr(0, colon);
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t") + 1);
    if (key.empty()) throw InputError(file_line(path, n), "calibration line has an empty key");
    if (entries_.count(key) > 0)
      throw InputError(file_line(path, n), "calibration key '" + key + "' repeated");
    entries_[key] = Entry{n, line.substr(colon + 1)};
    keys_.push_back(key);
  }
  if (in.bad()) throw InputError(path, "read error");
  if (keys_.empty()) throw InputError(path, "calibration file is empty");
}

std::vector<double> KeyValueFile::numbers(const std::string& key, std::size_t expected_count) const {
  const auto it = entries_.find(key);
  if (it == entries_.end()) throw InputError(path_, "calibration entry '" + key + "' is missing");
  const std::string where = file_line(path_, it->second.line);
  std::vector<double> v;
  if (!parse_number_list(it->second.text, v)) {
    throw InputError(where, "calibration entry '" + key + "' contains a token that is not a number");
  }
  if (expected_count > 0 && v.size() != expected_count) {
    throw InputError(where, "calibration entry '" + key + "' has " + std::to_string(v.size()) +
                                " values, expected " + std::to_string(expected_count));
  }
  for (double x : v) {
    if (!std::isfinite(x))
      throw InputError(where, "calibration entry '" + key + "' contains a non-finite value");
  }
  return v;
}

}  // namespace glmbslam::io::detail
