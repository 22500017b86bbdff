#pragma once
// Frame-to-frame stereo visual odometry: the previous good frame's triangulated points are matched into the
// current left image (descriptor search around their projection with the constant-velocity prediction), an
// EPnP + RANSAC pose seeds a motion-only refinement with the triangulation uncertainty folded into the
// residual weights (stereo_pose_refiner.hpp) that gives the relative pose and its covariance. A still scene
// is tracked like any other frame; only a byte-identical repeat of the previous pair (a duplicated frame in a
// log) is a repeat: zero motion with a small covariance. Hard frames (no features, too few matches or
// inliers, missing images) fall back to the constant-velocity prediction with an inflated covariance. With
// timestamps, the prediction and the fallback covariance scale with the time since the previous frame (a
// dropped frame); every frame gets exactly one estimate.
#include <cmath>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/lie.hpp"
#include "frontend/frontend_config.hpp"
#include "frontend/pixel_noise_estimator.hpp"
#include "frontend/stereo_frontend.hpp"
#include "frontend/stereo_pose_refiner.hpp"
#include "frontend/stereo_projection.hpp"

namespace glmbslam::frontend {

enum class VoStatus {
  kFirstFrame,     ///< first frame: identity, zero covariance
  kTracked,        ///< pose from PnP + refinement
  kNoFeatures,     ///< fallback: blank/empty image or too few stereo measurements
  kRepeatedImage,  ///< byte-identical repeat of the previous pair: zero motion, small covariance
  kTooFewMatches,  ///< fallback: guided matching found too few correspondences
  kTooFewInliers,  ///< fallback: PnP or refinement kept too few inliers
  kMissingImage,   ///< fallback: the frame could not be loaded (see skip_frame)
};
std::string to_string(VoStatus status);

/// Output for frame k.
struct VoEstimate {
  Pose3 relative_pose = Pose3::Identity();  ///< u_k = T_{k−1,k}: camera k expressed in camera k−1
  Matrix6d covariance = Matrix6d::Zero();  ///< Q_k of ξ in u_true = u_k · Exp(ξ), ξ = (ρ, φ) (core/lie.hpp)
  int matches = 0;                         ///< temporal correspondences found
  int inliers = 0;                         ///< correspondences kept by the refinement
  VoStatus status = VoStatus::kFirstFrame;
  /// Per measurement of this frame: the index of the previous frame's measurement it was tracked from (a
  /// refinement inlier whose previous observation was stereo), or −1. Empty on a fallback.
  std::vector<int> previous_measurement;
  /// The sequence's keypoint noise σ (px, level 0) estimated from the residuals up to this frame
  /// (pixel_noise_estimator.hpp; its initial value until enough frames were seen).
  double pixel_sigma = 1.0;
  bool pixel_sigma_estimated = false;  ///< pixel_sigma is an estimate (false: still the initial value)
  double ms = 0.0;                     ///< wall time of track()
  bool fallback() const {
    return status != VoStatus::kTracked && status != VoStatus::kFirstFrame &&
           status != VoStatus::kRepeatedImage;
  }
  bool repeated() const { return status == VoStatus::kRepeatedImage; }
};

class StereoVisualOdometry {
 public:
  /// `scales` are the pyramid scales of the extractor (scale_factor^level). `noise` configures the estimate
  /// of the keypoint noise (VoEstimate::pixel_sigma, for the backend). The refinement itself keeps weighing
  /// with the measurements' configured pixel_sigma: weighing it with the estimate (its Huber threshold and χ²
  /// gate in σ units) made the VO worse on KITTI raw 0001 (ATE 0.060 -> 0.091 m at an estimate of 0.89 px).
  StereoVisualOdometry(const StereoCamera& camera, const VoConfig& config, std::vector<double> scales,
                       const PixelNoiseOptions& noise = {});

  /// Estimates the motion from the previous frame to this one. `timestamp` (seconds; NaN: unknown, one
  /// nominal frame interval) scales the constant-velocity prediction with the time elapsed.
  VoEstimate track(const StereoFrameFeatures& frame, double timestamp = std::nan(""));

  /// A frame without usable images: constant-velocity fallback with status `reason`.
  VoEstimate skip_frame(VoStatus reason = VoStatus::kMissingImage, double timestamp = std::nan(""));

  /// The last track()'s motion re-estimated without the points whose current measurement is flagged in
  /// `excluded` (index-aligned with that frame's measurements): the refinement restarted from the full
  /// solution with the remaining points, with its own covariance. The backend takes this as its control when
  /// the flagged measurements are its own, so the same pixels are not counted twice (once in u_k and Q_k,
  /// once in the landmark updates). Returns `full` unchanged if it was a fallback or too few points remain.
  VoEstimate excluding(const VoEstimate& full, const std::vector<char>& excluded) const;

  /// Number of frames seen so far.
  std::size_t frames() const { return frames_; }
  /// The dataset index of the first frame tracked (a run over frames A:B starts at A): the messages name
  /// frames by their dataset index, as the rest of the run does.
  void set_first_frame(std::size_t index) { first_frame_ = index; }
  /// The keypoint noise estimate (pixel_noise_estimator.hpp).
  const PixelNoiseEstimator& pixel_noise() const { return noise_; }

 private:
  struct Reference {
    StereoMeasurementList measurements;
  };
  struct Match {
    int ref;  ///< index into reference measurements
    int cur;  ///< index into current left keypoints
    int distance;
  };

  std::vector<Match> guided_match(const StereoFrameFeatures& frame, const Pose3& T_ref_cur,
                                  double radius) const;
  /// The pyramid level at which a point of `octave` is expected after its depth shrank by `depth_ratio`
  /// (reference depth / current depth), within the extractor's levels.
  int predicted_octave(int octave, double depth_ratio) const;
  /// EPnP + RANSAC on (reference 3D point, current left pixel) of `matches`: true if it succeeds with at
  /// least min_inliers inliers (rvec, tvec: the current camera in the reference frame, OpenCV convention).
  bool pnp_ransac(const StereoFrameFeatures& frame, const std::vector<Match>& matches, cv::Mat& rvec,
                  cv::Mat& tvec, std::vector<int>& inliers) const;
  /// `matches` as refinement input (the current stereo measurement where there is one).
  struct TrackedPoints {
    std::vector<TrackedPoint> points;
    std::vector<int> ref, cur;  ///< per point: previous measurement, current one (−1: mono)
    std::vector<int> octaves;   ///< per point: the higher of its two keypoints' levels
  };
  TrackedPoints tracked_points(const StereoFrameFeatures& frame, const std::vector<Match>& matches) const;
  /// Guided matching around the predicted pose and EPnP-RANSAC: the matches, RANSAC's inliers among them and
  /// its pose; status kTracked, or the reason to fall back (kTooFewMatches, kTooFewInliers).
  struct RansacStart {
    std::vector<Match> matches;
    std::vector<int> inliers;
    Pose3 T_ref_cur = Pose3::Identity();
    VoStatus status = VoStatus::kTracked;
  };
  RansacStart ransac_start(const StereoFrameFeatures& frame, const Pose3& T_pred) const;
  /// The pairs the refinement takes: RANSAC's inliers, or (vo.rematch_after_pnp) guided matching again at
  /// its pose; with vo.consensus_first at the pose refined from RANSAC's inliers, which then becomes
  /// start.T_ref_cur, and opt gates at the start.
  std::vector<Match> refinement_matches(const StereoFrameFeatures& frame, RansacStart& start,
                                        PoseRefinementOptions& opt) const;
  /// The refined motion accepted: the estimate, and the state for the next frame and excluding().
  VoEstimate accept(const StereoFrameFeatures& frame, double timestamp, TrackedPoints tracked,
                    const PoseRefinementResult& res);
  VoEstimate fallback(VoStatus status);
  VoEstimate repeat() const;
  void set_reference(const StereoFrameFeatures& frame);
  bool repeated_image(const StereoFrameFeatures& frame);
  /// Sets the elapsed-time ratio of the current frame: (timestamp − previous frame's) / the interval of the
  /// last velocity (1 when either is unknown), and returns the constant-velocity motion over that time.
  Pose3 predicted_motion(double timestamp);
  /// Feeds the noise estimator with the refinement's residuals of the level-0 stereo points.
  void estimate_noise(const std::vector<TrackedPoint>& tracked, const std::vector<int>& octaves,
                      const PoseRefinementResult& res);

  StereoCamera camera_;
  VoConfig config_;
  std::vector<double> scales_;
  std::size_t frames_ = 0;
  std::size_t first_frame_ = 0;  ///< set_first_frame
  /// Frames given the constant-velocity fallback since the reference was taken (a dark stretch keeps it).
  std::size_t skipped_since_reference_ = 0;
  /// The frame being tracked is not the one after its reference: frames were skipped in between, or time
  /// passed for more than 1.5 frames (dropped frames).
  bool after_gap() const { return skipped_since_reference_ > 0 || time_ratio_ > 1.5; }
  /// The dataset index of the frame being tracked, for messages.
  std::size_t frame_label() const { return first_frame_ + frames_ - 1; }
  bool has_reference_ = false;
  Reference ref_;
  Pose3 T_ref_prev_ = Pose3::Identity();  ///< previous output frame expressed in the reference frame
  Pose3 velocity_ = Pose3::Identity();    ///< last relative motion (constant-velocity model)
  double velocity_dt_ = std::nan("");     ///< the time that motion took (NaN: unknown)
  double previous_time_ = std::nan("");   ///< timestamp of the previous output pose (a repeat keeps it)
  double current_time_ = std::nan("");    ///< timestamp of the frame being tracked
  double time_ratio_ = 1.0;               ///< elapsed time of the frame being tracked / velocity_dt_
  Matrix6d last_covariance_ = Matrix6d::Zero();
  bool velocity_known_ = false;
  // The last successful track(): its refinement input, the current measurement of each point (−1: mono),
  // the refined T_ref_cur and the reference-to-previous transform it was expressed with.
  std::vector<TrackedPoint> last_tracked_;
  std::vector<int> last_tracked_current_;
  Pose3 last_T_ref_cur_ = Pose3::Identity();
  Pose3 last_T_ref_prev_ = Pose3::Identity();
  cv::Mat previous_left_, previous_right_;  ///< copies of the previous pair (repeat detection)
  PixelNoiseEstimator noise_;
};

}  // namespace glmbslam::frontend
