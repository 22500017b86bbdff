#pragma once
// Shared by the libFuzzer targets: every parser under test reads a path, so each input is written to a file
// in a per-process scratch folder (in /dev/shm when it exists) and the reader is called on it. A reader may
// reject the input only with the project's InputError / ConfigError; any other exception, crash, hang or
// sanitizer report is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"

namespace glmbslam::fuzz {

/// The scratch folder of this process (created on first use).
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path base = std::filesystem::exists("/dev/shm")
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    std::filesystem::path d = base / ("glmbslam_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes `size` bytes to `relative` inside the scratch folder; returns the full path.
inline std::string write_input(const std::string& relative, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = scratch_dir() / relative;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

inline std::string write_text(const std::string& relative, const std::string& text) {
  return write_input(relative, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

/// Calls `read()`; the project's documented rejections (InputError, ConfigError) are accepted.
template <class F>
void expect_clean_rejection(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const ConfigError&) {
  }
}

}  // namespace glmbslam::fuzz
