#pragma once
// The image files of a stereo sequence's camera: one folder and the file names in frame order. A parsed
// std::filesystem::path per frame costs ~440 bytes (its component list); a name costs ~32, so the list of a
// 20 000-frame sequence takes ~1 MB instead of ~17 MB for both cameras.
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace glmbslam::io {

class ImageFileList {
 public:
  ImageFileList() = default;
  explicit ImageFileList(std::filesystem::path folder) : folder_(std::move(folder)) {}

  void push_back(std::string name) { names_.push_back(std::move(name)); }
  std::size_t size() const { return names_.size(); }
  bool empty() const { return names_.empty(); }
  /// The file name of frame i (relative to the folder).
  const std::string& name(std::size_t i) const { return names_[i]; }
  /// The full path of frame i.
  std::filesystem::path path(std::size_t i) const { return folder_ / names_[i]; }
  const std::filesystem::path& folder() const { return folder_; }

 private:
  std::filesystem::path folder_;
  std::vector<std::string> names_;
};

}  // namespace glmbslam::io
