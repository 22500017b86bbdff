#pragma once
// Stage 2 of the stereo pipeline (VO): the frame-to-frame visual odometry on the frontend's features. Its
// relative motion u_k and covariance Q_k are the backend's control; their product is vo_trajectory.txt.
#include <cstddef>

#include "app/pipeline/frame_source.hpp"
#include "core/types.hpp"
#include "frontend/visual_odometry.hpp"

namespace glmbslam::app {

class VoStage {
 public:
  /// `noise`: the settings of the VO's keypoint noise estimate (VoEstimate::pixel_sigma).
  VoStage(const frontend::StereoFrontend& frontend, const frontend::VoConfig& config,
          const frontend::PixelNoiseOptions& noise = {});

  /// Tracks frame `work` (the run's k-th frame, at work.timestamp) and accumulates the VO pose. An unreadable
  /// frame gets the constant-velocity fallback over its elapsed time (identity at k = 0).
  const frontend::VoEstimate& track(const FrameWork& work, std::size_t k);

  /// The dataset index of the run's first frame (the VO's messages name frames by it).
  void set_first_frame(std::size_t index) { vo_.set_first_frame(index); }
  const frontend::VoEstimate& estimate() const { return estimate_; }
  /// The accumulated VO pose T_0k of the last tracked frame.
  const Pose3& pose() const { return pose_; }
  const frontend::StereoVisualOdometry& odometry() const { return vo_; }
  std::size_t fallbacks() const { return fallbacks_; }  ///< frames tracked without a VO solution
  std::size_t missing() const { return missing_; }      ///< frames whose images could not be read
  std::size_t repeated() const { return repeated_; }    ///< byte-identical repeats of the previous pair

 private:
  frontend::StereoVisualOdometry vo_;
  frontend::VoEstimate estimate_;
  Pose3 pose_ = Pose3::Identity();
  std::size_t fallbacks_ = 0, missing_ = 0, repeated_ = 0;
};

}  // namespace glmbslam::app
