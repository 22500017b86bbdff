#pragma once
// CLI11 checks with messages a user can read: CLI::PositiveNumber reports "Value 0 not in range 0 to
// 1.797…e308" with the double's maximum written out in full.
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

namespace glmbslam::app {

/// Accepts a number greater than zero; otherwise "must be a positive number, got 'X'".
inline CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          std::size_t used = 0;
          const double v = std::stod(text, &used);
          if (used == text.size() && v > 0.0) return "";
        } catch (const std::exception&) {
        }
        return "must be a positive number, got '" + text + "'";
      },
      "POSITIVE");
}

}  // namespace glmbslam::app
