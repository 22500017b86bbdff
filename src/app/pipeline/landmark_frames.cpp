#include "app/pipeline/landmark_frames.hpp"

#include <cstddef>

#include "app/pipeline/filter_stage.hpp"

namespace glmbslam::app {

void move_with_birth_frames(std::vector<io::MapPoint>& map, const PoseList& from, const PoseList& to) {
  for (auto& p : map) {
    const std::size_t birth = label_birth_step(p.label);
    if (birth < from.size() && birth < to.size())
      p.position = to[birth] * (from[birth].inverse() * p.position);
  }
}

}  // namespace glmbslam::app
