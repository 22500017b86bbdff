#pragma once
// Options of the glmbslam executable that apply to every subcommand (main.cpp), visible to the subcommands so
// a value given on the command line wins over the same key in a config file.
#include <optional>

namespace glmbslam::app {

struct GlobalOptions {
  std::optional<int> threads;  ///< --threads when given (0 = all cores); a config's `threads:` yields to it
};

/// The process-wide global options (set once by main before the subcommand runs).
GlobalOptions& global_options();

}  // namespace glmbslam::app
