#include "app/global_options.hpp"

namespace glmbslam::app {

GlobalOptions& global_options() {
  static GlobalOptions options;
  return options;
}

}  // namespace glmbslam::app
