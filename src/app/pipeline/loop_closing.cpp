#include "app/pipeline/loop_closing.hpp"

#include <utility>

#include <spdlog/spdlog.h>

#include "app/pipeline/landmark_frames.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::app {

LoopClosing::LoopClosing(const LoopDetectorOptions& options, const StereoCalibration& calibration)
    : detector_(options, calibration) {}

void LoopClosing::add_frame(std::size_t k, const frontend::StereoMeasurementList& measurements) {
  detector_.add_frame(k, measurements);
}

int LoopClosing::apply(PoseList& poses, std::vector<io::MapPoint>& map,
                       const std::vector<backend::RelativePoseControl,
                                         Eigen::aligned_allocator<backend::RelativePoseControl>>& controls,
                       std::map<std::string, double>& stats) const {
  Stopwatch watch;
  const std::vector<backend::LoopConstraint> loops = detector_.detect(poses);
  stats["loops_detected"] = static_cast<double>(loops.size());
  int used = 0;
  if (!loops.empty() && controls.size() == poses.size()) {
    backend::Matrix6dVector covariance(poses.size(), Matrix6d::Identity());
    for (std::size_t k = 1; k < poses.size(); ++k) covariance[k] = controls[k].covariance;
    backend::PoseVector corrected(poses.begin(), poses.end());
    const backend::LoopPoseGraphReport r = backend::optimise_loop_pose_graph(corrected, covariance, loops);
    used = r.loops_used;
    stats["loops_rejected"] = r.loops_rejected;
    // each landmark moves with the correction of the frame that first mapped it (its label's birth step)
    PoseList bent(corrected.begin(), corrected.end());
    move_with_birth_frames(map, poses, bent);
    poses = std::move(bent);
    spdlog::info("refinement: {} loop constraints from {} keyframes, {} kept by the pose graph", loops.size(),
                 detector_.keyframes(), used);
  }
  stats["loops"] = used;
  stats["loop_ms"] = watch.elapsed_ms();
  return used;
}

}  // namespace glmbslam::app
