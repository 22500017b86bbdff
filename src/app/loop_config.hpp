#pragma once
// The `refine.loop` mapping of the stereo config: the revisit detection of the refinement's loop closing
// (app/pipeline/loop_detector.hpp; config/kitti00-02.yaml documents every key).
#include "app/pipeline/loop_detector.hpp"
#include "core/config_node.hpp"

namespace glmbslam::app {

/// Reads `node` over `o`; throws ConfigError naming the key on a bad value.
void load_loop_config(ConfigNode node, LoopDetectorOptions& o);

}  // namespace glmbslam::app
