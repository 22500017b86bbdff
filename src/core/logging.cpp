#include "core/logging.hpp"

#include "core/error.hpp"

#include <string>

#include <unistd.h>

namespace glmbslam {

void set_log_level(const std::string& level) {
  const auto parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off") {
    throw ConfigError("unknown log level '" + level + "' (use trace, debug, info, warn, error or off)");
  }
  spdlog::set_level(parsed);
  // On a terminal a log line first clears the line it starts on, so it never runs on after a progress bar
  // (core/progress.hpp) that is being redrawn there; the bar reappears below it at its next update.
  const bool terminal = ::isatty(STDOUT_FILENO) != 0 && ::isatty(STDERR_FILENO) != 0;
  spdlog::set_pattern(std::string(terminal ? "\r\033[K" : "") + "[%H:%M:%S.%e] [%^%l%$] %v");
}

}  // namespace glmbslam
