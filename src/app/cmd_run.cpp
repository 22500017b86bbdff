// Placeholder: replaced by the issue that implements `glmbslam run`.
#include <stdexcept>

#include "app/commands.hpp"

namespace glmbslam::app {

void register_run_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "(not yet available)");
  cmd->callback([] { throw std::runtime_error("glmbslam run is not available in this build yet"); });
}

}  // namespace glmbslam::app
