#pragma once
// Moving the filter's map with a corrected trajectory: each landmark keeps its position relative to the frame
// that first mapped it (its δ-GLMB label's birth step), so a landmark follows the correction of the part of
// the trajectory it was built from. Used by the loop closing (the pose graph's correction) and by the final
// refinement pass when it starts from the online windows' trajectory.
#include <vector>

#include "core/types.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::app {

/// Moves every landmark of `map` (labels birth step << 12 | index, filter_stage.hpp) from the frame of
/// `from[birth]` to the frame of `to[birth]`: p ← to[birth] · from[birth]⁻¹ · p. Landmarks whose birth step
/// is outside both trajectories stay where they are.
void move_with_birth_frames(std::vector<io::MapPoint>& map, const PoseList& from, const PoseList& to);

}  // namespace glmbslam::app
