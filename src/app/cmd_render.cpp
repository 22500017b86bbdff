// Placeholder: replaced by the issue that implements `glmbslam render`.
#include <stdexcept>

#include "app/commands.hpp"

namespace glmbslam::app {

void register_render_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("render", "(not yet available)");
  cmd->callback([] { throw std::runtime_error("glmbslam render is not available in this build yet"); });
}

}  // namespace glmbslam::app
