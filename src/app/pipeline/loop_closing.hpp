#pragma once
// Loop closing of the stereo refinement (refine.loop_closure, `glmbslam run --refine ml`): keyframes
// collected while the run goes (loop_detector.hpp), then, before the final RFS-ML pass, revisits detected
// along the final pass's starting trajectory (the windows' or the filter's, refine.final_start), the
// trajectory bent by the pose graph (backend/mlslam/loop_pose_graph.hpp) and each landmark moved with the
// correction of the frame that first mapped it, so that the final pass starts with the two visits of a place
// close enough for its E-step to associate them.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "app/pipeline/loop_detector.hpp"
#include "backend/models/se3_motion.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::app {

class LoopClosing {
 public:
  LoopClosing(const LoopDetectorOptions& options, const StereoCalibration& calibration);

  /// Frame k of the run and its stereo measurements (all of them, not only those handed to the filter).
  void add_frame(std::size_t k, const frontend::StereoMeasurementList& measurements);

  /// Closes the loops of the run in place: `poses` (one per frame, the filter's) and `map` (landmark labels
  /// birth step << 12 | index, app/pipeline/filter_stage.hpp) move; `controls[k]` (k ≥ 1) weighs the motion
  /// of frame k. Adds `loops_detected`, `loops` (kept), `loops_rejected` and `loop_ms` to `stats`; returns
  /// the loops kept.
  int apply(PoseList& poses, std::vector<io::MapPoint>& map,
            const std::vector<backend::RelativePoseControl,
                              Eigen::aligned_allocator<backend::RelativePoseControl>>& controls,
            std::map<std::string, double>& stats) const;

 private:
  LoopDetector detector_;
};

}  // namespace glmbslam::app
