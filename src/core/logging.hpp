#pragma once
// Logging through spdlog; one call sets the level for the whole program.
#include <string>

#include <spdlog/spdlog.h>

namespace glmbslam {

/// Sets the global log level from a name: trace, debug, info, warn, error, off. Throws ConfigError otherwise.
void set_log_level(const std::string& level);

}  // namespace glmbslam
