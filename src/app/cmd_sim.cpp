// Placeholder: replaced by the issue that implements `glmbslam sim`.
#include <stdexcept>

#include "app/commands.hpp"

namespace glmbslam::app {

void register_sim_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("sim", "(not yet available)");
  cmd->callback([] { throw std::runtime_error("glmbslam sim is not available in this build yet"); });
}

}  // namespace glmbslam::app
