#pragma once
// Small helpers shared by the KITTI readers (odometry and raw): number parsing, image listing, image loading,
// and "key: numbers" calibration files. Every failure is an InputError naming the file and the problem.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/types.hpp"
#include "io/image_file_list.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::io::detail {

/// "path:line" for error messages.
std::string file_line(const std::string& path, std::size_t line);

/// Splits `text` into numbers; returns false if a token is not a number. Non-finite values are returned as
/// parsed.
bool parse_number_list(const std::string& text, std::vector<double>& out);

/// True if the line holds only white space.
bool is_blank_line(const std::string& line);

/// The *.png files in `dir`, sorted by name. Throws InputError naming `dir` if it is not a folder or has no
/// PNG.
ImageFileList list_png_files(const std::filesystem::path& dir);

/// Checks that the two cameras' lists pair up name by name. Throws InputError naming the first image without
/// a partner in the other camera's folder, with both folders' image counts (folders named relative to `dir`).
void require_stereo_pairs(const std::filesystem::path& dir, const ImageFileList& left,
                          const ImageFileList& right);

/// Checks that `dir` exists and is a folder; throws InputError naming it otherwise (`what` describes the
/// folder).
void require_directory(const std::filesystem::path& dir, const std::string& what);

/// Checks that `file` exists and is a regular file; throws InputError naming it otherwise.
void require_file(const std::filesystem::path& file, const std::string& what);

/// A 16-bit grey image scaled to 8 bits by the bit depth its values use (the smallest b ≥ 8 with max < 2^b:
/// cameras store 10- or 12-bit data in 16-bit PNGs, and OpenCV's own conversion keeps the high byte, which
/// leaves a 12-bit image at grey levels 0–15).
cv::Mat gray16_to_8bit(const cv::Mat& image);

/// Reads a grayscale image as 8 bits (colour converted to grey, 16-bit by gray16_to_8bit); throws InputError
/// naming the file if missing or unreadable, or if its size is not width×height (when width > 0).
cv::Mat read_gray_image(const std::filesystem::path& file, int width = 0, int height = 0);

/// Image i of one side's image list (8-bit, width×height when width > 0). Throws InputError naming `name`
/// if i is out of range, or naming the image file if it is missing or unreadable.
cv::Mat read_stereo_image(const std::string& name, std::size_t i, const ImageFileList& files, int width,
                          int height);

/// Sets calib.width/height from the first image and checks that the calibration belongs to images of that
/// size: the principal point must lie inside the image (a calibration of another camera or resolution usually
/// puts it outside). Throws InputError naming `calib_path` otherwise.
void fit_calibration_to_image(StereoCalibration& calib, const cv::Mat& first_image,
                              const std::string& calib_path, const std::string& image_path);

/// A "key: n1 n2 ..." text file (KITTI calib files). Lines whose values are not all numbers are kept as
/// non-numeric (e.g. calib_time); asking for such a key as numbers is an error.
class KeyValueFile {
 public:
  explicit KeyValueFile(const std::string& path);
  const std::string& path() const { return path_; }
  bool has(const std::string& key) const { return entries_.count(key) > 0; }
  /// The numbers of `key`; throws InputError naming the file and line if absent, not numeric, of the wrong
  /// count (when expected_count > 0) or non-finite.
  std::vector<double> numbers(const std::string& key, std::size_t expected_count) const;
  /// Keys in file order.
  const std::vector<std::string>& keys() const { return keys_; }

 private:
  struct Entry {
    std::size_t line = 0;
    std::string text;
  };
  std::string path_;
  std::map<std::string, Entry> entries_;
  std::vector<std::string> keys_;
};

}  // namespace glmbslam::io::detail
