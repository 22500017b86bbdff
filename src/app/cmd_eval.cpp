// Placeholder: replaced by the issue that implements `glmbslam eval`.
#include <stdexcept>

#include "app/commands.hpp"

namespace glmbslam::app {

void register_eval_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "(not yet available)");
  cmd->callback([] { throw std::runtime_error("glmbslam eval is not available in this build yet"); });
}

}  // namespace glmbslam::app
