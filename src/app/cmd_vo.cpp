// Placeholder: replaced by the issue that implements `glmbslam vo`.
#include <stdexcept>

#include "app/commands.hpp"

namespace glmbslam::app {

void register_vo_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("vo", "(not yet available)");
  cmd->callback([] { throw std::runtime_error("glmbslam vo is not available in this build yet"); });
}

}  // namespace glmbslam::app
