#pragma once
// Errors raised on bad input. The message always names the file (or setting) and the problem, on one line.
#include <stdexcept>
#include <string>

namespace glmbslam {

/// Bad input data: a file that is missing, malformed, inconsistent or non-finite.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& problem)
      : std::runtime_error(file + ": " + problem), file_(file), problem_(problem) {}
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

/// Bad configuration: an unknown key, a value of the wrong type or out of range.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace glmbslam
