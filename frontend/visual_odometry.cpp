#include "frontend/visual_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include <spdlog/spdlog.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "core/stopwatch.hpp"
#include "frontend/stereo_pose_refiner.hpp"

namespace glmbslam::frontend {

std::string to_string(VoStatus status) {
  switch (status) {
    case VoStatus::kFirstFrame:
      return "first_frame";
    case VoStatus::kTracked:
      return "tracked";
    case VoStatus::kNoFeatures:
      return "no_features";
    case VoStatus::kRepeatedImage:
      return "repeated_image";
    case VoStatus::kTooFewMatches:
      return "too_few_matches";
    case VoStatus::kTooFewInliers:
      return "too_few_inliers";
    case VoStatus::kMissingImage:
      return "missing_image";
  }
  return "unknown";
}

StereoVisualOdometry::StereoVisualOdometry(const StereoCamera& camera, const VoConfig& config,
                                           std::vector<double> scales, const PixelNoiseOptions& noise)
    : camera_(camera), config_(config), scales_(std::move(scales)), noise_(noise) {}

void StereoVisualOdometry::estimate_noise(const std::vector<TrackedPoint>& tracked,
                                          const std::vector<int>& octaves, const PoseRefinementResult& res) {
  if (res.chi2.size() != tracked.size()) return;
  std::vector<double> unit_chi2;
  std::vector<double> flow;
  int fit_dimensions = 0;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    const TrackedPoint& t = tracked[i];
    if (res.inlier[i]) fit_dimensions += t.cur_stereo ? 3 : 2;
    // level-0 stereo points on both frames: the noise the backend's model describes, one σ for both
    if (!t.cur_stereo || octaves[i] != 0 || !std::isfinite(res.chi2[i])) continue;
    unit_chi2.push_back(res.chi2[i] * t.sigma_ref * t.sigma_ref);
    flow.push_back((t.z_cur.head<2>() - t.z_ref.head<2>()).norm());
  }
  if (flow.empty()) return;
  const auto mid = flow.begin() + static_cast<std::ptrdiff_t>(flow.size() / 2);
  std::nth_element(flow.begin(), mid, flow.end());
  const bool used = noise_.add_frame(unit_chi2, fit_dimensions, *mid);
  spdlog::debug("vo: frame {}: {} level-0 residuals, median motion {:.1f} px{}, keypoint sigma {:.3f} px",
                frame_label(), unit_chi2.size(), *mid, used ? "" : " (not used)", noise_.sigma());
}

bool StereoVisualOdometry::pnp_ransac(const StereoFrameFeatures& frame, const std::vector<Match>& matches,
                                      cv::Mat& rvec, cv::Mat& tvec, std::vector<int>& inliers) const {
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  object.reserve(matches.size());
  image.reserve(matches.size());
  for (const Match& m : matches) {
    const Eigen::Vector3d& X = ref_.measurements[static_cast<std::size_t>(m.ref)].point;
    object.emplace_back(static_cast<float>(X.x()), static_cast<float>(X.y()), static_cast<float>(X.z()));
    image.push_back(frame.left.keypoints[static_cast<std::size_t>(m.cur)].pt);
  }
  const cv::Matx33d K(camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  inliers.clear();
  bool ok = false;
  try {
    ok = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, config_.ransac_iterations,
                            static_cast<float>(config_.ransac_reprojection_px), config_.ransac_confidence,
                            inliers, cv::SOLVEPNP_EPNP);
  } catch (const cv::Exception& ex) {
    spdlog::debug("vo: frame {}: solvePnPRansac failed: {}", frame_label(), ex.what());
    ok = false;
  }
  return ok && static_cast<int>(inliers.size()) >= config_.min_inliers;
}

VoEstimate StereoVisualOdometry::fallback(VoStatus status) {
  VoEstimate e;
  e.status = status;
  e.relative_pose = time_ratio_ == 1.0 ? velocity_ : se3_exp(time_ratio_ * se3_log(velocity_));
  Matrix6d floor = Matrix6d::Zero();
  const double st = config_.fallback_sigma_translation_m, sr = config_.fallback_sigma_rotation_rad;
  floor.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sr * sr;
  // an error δv of the velocity grows to (Δt/Δt_v)·δv over the elapsed time: covariance × ratio²
  const double grow = std::max(1.0, time_ratio_ * time_ratio_);
  e.covariance = grow * (config_.fallback_covariance_scale * last_covariance_ + floor);
  T_ref_prev_ = T_ref_prev_ * e.relative_pose;
  ++skipped_since_reference_;
  previous_time_ = current_time_;
  return e;
}

VoEstimate StereoVisualOdometry::repeat() const {
  VoEstimate e;
  e.status = VoStatus::kRepeatedImage;
  const double st = config_.repeat_sigma_translation_m, sr = config_.repeat_sigma_rotation_rad;
  e.covariance.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sr * sr;
  return e;
}

Pose3 StereoVisualOdometry::predicted_motion(double timestamp) {
  current_time_ = timestamp;
  time_ratio_ = 1.0;
  const double dt = timestamp - previous_time_;
  if (std::isfinite(dt) && dt > 0.0 && std::isfinite(velocity_dt_) && velocity_dt_ > 0.0) {
    time_ratio_ = std::min(dt / velocity_dt_, 20.0);
  }
  return time_ratio_ == 1.0 ? velocity_ : se3_exp(time_ratio_ * se3_log(velocity_));
}

VoEstimate StereoVisualOdometry::skip_frame(VoStatus reason, double timestamp) {
  Stopwatch sw;
  ++frames_;
  predicted_motion(timestamp);
  VoEstimate e = frames_ == 1 ? VoEstimate{} : fallback(reason);
  if (frames_ == 1) {
    e.status = reason;
    previous_time_ = timestamp;
  }
  // the caller names the frame and why it could not be read
  spdlog::debug("vo: frame {}: {} → constant-velocity fallback", frame_label(), to_string(reason));
  e.pixel_sigma = noise_.sigma();
  e.pixel_sigma_estimated = noise_.estimated();
  e.ms = sw.elapsed_ms();
  return e;
}

void StereoVisualOdometry::set_reference(const StereoFrameFeatures& frame) {
  ref_.measurements = frame.measurements;
  has_reference_ = true;
  T_ref_prev_ = Pose3::Identity();
  skipped_since_reference_ = 0;
}

namespace {

bool same_bytes(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty() || a.size() != b.size() || a.type() != b.type()) return false;
  const std::size_t row_bytes = a.cols * a.elemSize();
  for (int r = 0; r < a.rows; ++r) {
    if (std::memcmp(a.ptr(r), b.ptr(r), row_bytes) != 0) return false;
  }
  return true;
}

const cv::Mat& level0(const OrbFeatures& f) {
  static const cv::Mat none;
  return f.pyramid.empty() ? none : f.pyramid.front();
}

}  // namespace

bool StereoVisualOdometry::repeated_image(const StereoFrameFeatures& frame) {
  const cv::Mat &left = level0(frame.left), &right = level0(frame.right);
  // both images byte-identical to the previous pair (a blank right image counts as identical to a blank one)
  const bool repeated = same_bytes(left, previous_left_) &&
                        (right.empty() ? previous_right_.empty() : same_bytes(right, previous_right_));
  if (!repeated) {
    left.copyTo(previous_left_);
    right.copyTo(previous_right_);
  }
  return repeated;
}

int StereoVisualOdometry::predicted_octave(int octave, double depth_ratio) const {
  // A point seen from depth_ratio times closer appears depth_ratio times larger: the extractor finds it that
  // many pyramid scales coarser (ORB-SLAM's scale prediction). Frame to frame the ratio is near 1 and the
  // octave stays; after a gap (dark frames, a dropped stretch) the prediction keeps the near points.
  if (scales_.size() < 2 || !(depth_ratio > 0.0) || !std::isfinite(depth_ratio)) return octave;
  const double shift = std::log(depth_ratio) / std::log(scales_[1] / scales_[0]);
  const long predicted = static_cast<long>(octave) + std::lround(shift);
  return static_cast<int>(std::clamp(predicted, 0L, static_cast<long>(scales_.size()) - 1));
}

std::vector<StereoVisualOdometry::Match> StereoVisualOdometry::guided_match(const StereoFrameFeatures& frame,
                                                                            const Pose3& T_ref_cur,
                                                                            double radius) const {
  const auto& kps = frame.left.keypoints;
  std::vector<Match> matches;
  if (kps.empty() || frame.left.pyramid.empty()) return matches;
  // Grid of the current left keypoints (cells of `cell` pixels at level 0).
  const int cell = 32;
  const int width = frame.left.pyramid[0].cols, height = frame.left.pyramid[0].rows;
  const int gc = width / cell + 1, gr = height / cell + 1;
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(gc * gr));
  for (int j = 0; j < static_cast<int>(kps.size()); ++j) {
    const int cx = std::clamp(static_cast<int>(kps[j].pt.x) / cell, 0, gc - 1);
    const int cy = std::clamp(static_cast<int>(kps[j].pt.y) / cell, 0, gr - 1);
    grid[static_cast<std::size_t>(cy * gc + cx)].push_back(j);
  }
  const Pose3 T_cur_ref = T_ref_cur.inverse();
  std::vector<int> owner(kps.size(), -1);  // current keypoint → index into matches
  matches.reserve(ref_.measurements.size());
  for (int i = 0; i < static_cast<int>(ref_.measurements.size()); ++i) {
    const StereoMeasurement& m = ref_.measurements[static_cast<std::size_t>(i)];
    const Eigen::Vector3d pc = T_cur_ref * m.point;
    if (pc.z() <= 0.1) continue;
    const Eigen::Vector3d z = camera_.project(pc);
    if (z.x() < 0 || z.y() < 0 || z.x() >= width || z.y() >= height) continue;
    // the pyramid levels searched: the reference's ±1; after a gap, around the level the depth change
    // predicts (frame to frame, the near points whose scale changes that much match poorly and stay out)
    const int octave = after_gap() ? predicted_octave(m.octave, m.point.z() / pc.z()) : m.octave;
    const int lowest = std::min(m.octave, octave) - 1, highest = std::max(m.octave, octave) + 1;
    const double r = radius * scales_[static_cast<std::size_t>(m.octave)];
    const int x0 = std::max(0, static_cast<int>((z.x() - r) / cell)),
              x1 = std::min(gc - 1, static_cast<int>((z.x() + r) / cell));
    const int y0 = std::max(0, static_cast<int>((z.y() - r) / cell)),
              y1 = std::min(gr - 1, static_cast<int>((z.y() + r) / cell));
    int best = std::numeric_limits<int>::max(), second = std::numeric_limits<int>::max(), best_j = -1;
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        for (int j : grid[static_cast<std::size_t>(cy * gc + cx)]) {
          const cv::KeyPoint& k = kps[static_cast<std::size_t>(j)];
          if (k.octave < lowest || k.octave > highest) continue;
          const double du = k.pt.x - z.x(), dv = k.pt.y - z.y();
          if (du * du + dv * dv > r * r) continue;
          const int d = hamming_distance(m.descriptor.data(), frame.left.descriptors.ptr<uchar>(j));
          if (d < best) {
            second = best;
            best = d;
            best_j = j;
          } else if (d < second) {
            second = d;
          }
        }
      }
    }
    if (best_j < 0 || best >= config_.max_hamming) continue;
    if (config_.ratio < 1.0 && second != std::numeric_limits<int>::max() && best >= config_.ratio * second)
      continue;
    int& o = owner[static_cast<std::size_t>(best_j)];
    if (o >= 0) {
      if (matches[static_cast<std::size_t>(o)].distance <= best) continue;
      matches[static_cast<std::size_t>(o)] = {i, best_j, best};
    } else {
      o = static_cast<int>(matches.size());
      matches.push_back({i, best_j, best});
    }
  }
  return matches;
}

VoEstimate StereoVisualOdometry::track(const StereoFrameFeatures& frame, double timestamp) {
  Stopwatch sw;
  ++frames_;
  const std::size_t k = frames_ - 1;
  const std::size_t label = frame_label();
  auto finish = [&](VoEstimate e) {
    e.pixel_sigma = noise_.sigma();
    e.pixel_sigma_estimated = noise_.estimated();
    e.ms = sw.elapsed_ms();
    return e;
  };
  const int min_measurements = std::max(config_.min_inliers, 8);
  const bool repeated = k > 0 && repeated_image(frame);
  if (k == 0) repeated_image(frame);  // remembers the pair
  // A textured pair repeated shows the previous pose: zero motion, the clock of the prediction not advanced.
  // A pair with too few measurements to track (a dark or covered lens) repeated says nothing about the
  // motion: it goes on below to the constant-velocity fallback like the first such pair.
  if (repeated && static_cast<int>(frame.measurements.size()) >= min_measurements) {
    spdlog::info("vo: frame {}: stereo pair identical to the previous one → zero motion", label);
    return finish(repeat());
  }
  const Pose3 velocity = predicted_motion(timestamp);
  if (!has_reference_) {
    // nothing to track from yet (the first frame, or only too dark or blank ones so far): this frame becomes
    // the reference if it can be; its motion since the previous frame is the prediction (zero at the start)
    const bool usable = static_cast<int>(frame.measurements.size()) >= min_measurements;
    VoEstimate e;
    e.status = VoStatus::kFirstFrame;
    if (k > 0) {
      e = fallback(usable ? VoStatus::kFirstFrame : VoStatus::kNoFeatures);
      if (usable) {
        spdlog::info("vo: frame {}: the first frame to track from; its motion since frame {} is not known",
                     label, label - 1);
      } else {
        spdlog::warn(
            "vo: frame {}: {} stereo measurements and no frame to track from yet → constant-velocity "
            "fallback",
            label, frame.measurements.size());
      }
    }
    previous_time_ = timestamp;
    if (usable) set_reference(frame);
    return finish(e);
  }
  if (static_cast<int>(frame.measurements.size()) < min_measurements) {
    spdlog::warn("vo: frame {}: {} stereo measurements → constant-velocity fallback", label,
                 frame.measurements.size());
    return finish(fallback(VoStatus::kNoFeatures));
  }

  // A lost frame: constant velocity, and the current frame becomes the reference.
  auto lost = [&](VoStatus status, std::size_t matches) {
    VoEstimate e = fallback(status);
    e.matches = static_cast<int>(matches);
    set_reference(frame);
    return finish(e);
  };
  RansacStart start = ransac_start(frame, T_ref_prev_ * velocity);
  if (start.status != VoStatus::kTracked) return lost(start.status, start.matches.size());
  PoseRefinementOptions opt = pose_refinement_options(config_);
  const std::vector<Match> matches = refinement_matches(frame, start, opt);

  // Two-view stereo bundle adjustment.
  TrackedPoints tracked = tracked_points(frame, matches);
  const PoseRefinementResult res = refine_stereo_pose(camera_, tracked.points, start.T_ref_cur, opt);
  if (!res.success || res.inliers < config_.min_inliers) {
    spdlog::warn("vo: frame {}: refinement kept {} of {} points → constant-velocity fallback", label,
                 res.inliers, tracked.points.size());
    return lost(VoStatus::kTooFewInliers, matches.size());
  }
  VoEstimate e = accept(frame, timestamp, std::move(tracked), res);
  // the temporal correspondences found: the rematch's, or all that RANSAC saw
  e.matches = static_cast<int>(config_.rematch_after_pnp ? matches.size() : start.matches.size());
  return finish(e);
}

StereoVisualOdometry::RansacStart StereoVisualOdometry::ransac_start(const StereoFrameFeatures& frame,
                                                                     const Pose3& T_pred) const {
  // Guided matching with the constant-velocity prediction, then EPnP + RANSAC on (reference 3D point, current
  // left pixel). The wide window is used when the velocity is unknown, and tried again when the narrow one
  // finds too few matches or matches that PnP rejects (a sharp turn moves the features beyond the narrow
  // window, which then holds mostly wrong candidates).
  const std::size_t k = frame_label();
  RansacStart start;
  cv::Mat rvec, tvec;
  bool ok = false;
  for (int attempt = velocity_known_ ? 0 : 1; attempt < 2 && !ok; ++attempt) {
    const double radius = attempt == 0 ? config_.search_radius_px : config_.wide_search_radius_px;
    start.matches = guided_match(frame, T_pred, radius);
    if (static_cast<int>(start.matches.size()) < config_.min_matches) continue;
    ok = pnp_ransac(frame, start.matches, rvec, tvec, start.inliers);
    if (!ok && attempt == 0) {
      spdlog::debug("vo: frame {}: PnP kept {} of {} matches in the narrow window, trying the wide one", k,
                    start.inliers.size(), start.matches.size());
    }
  }
  if (static_cast<int>(start.matches.size()) < config_.min_matches) {
    spdlog::warn("vo: frame {}: {} temporal matches → constant-velocity fallback", k, start.matches.size());
    start.status = VoStatus::kTooFewMatches;
    return start;
  }
  if (!ok) {
    spdlog::warn("vo: frame {}: PnP kept {} of {} matches → constant-velocity fallback", k,
                 start.inliers.size(), start.matches.size());
    start.status = VoStatus::kTooFewInliers;
    return start;
  }
  cv::Matx33d Rcv;
  cv::Rodrigues(rvec, Rcv);
  Pose3 T_cur_ref = Pose3::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T_cur_ref.linear()(r, c) = Rcv(r, c);
    T_cur_ref.translation()(r) = tvec.at<double>(r);
  }
  start.T_ref_cur = T_cur_ref.inverse();
  start.status = VoStatus::kTracked;
  return start;
}

std::vector<StereoVisualOdometry::Match> StereoVisualOdometry::refinement_matches(
    const StereoFrameFeatures& frame, RansacStart& start, PoseRefinementOptions& opt) const {
  auto consensus_matches = [&start] {  // RANSAC's inliers
    std::vector<Match> inliers;
    inliers.reserve(start.inliers.size());
    for (int i : start.inliers) inliers.push_back(start.matches[static_cast<std::size_t>(i)]);
    return inliers;
  };
  if (!config_.rematch_after_pnp) return consensus_matches();
  if (config_.consensus_first) {
    // The RANSAC consensus alone first, and the rematched pairs gated at its pose: a Huber solve from the
    // RANSAC pose over all rematched pairs lets a well-textured moving car pull the motion to a compromise
    // both fit (docs/investigations.md "Moving objects").
    const PoseRefinementResult consensus =
        refine_stereo_pose(camera_, tracked_points(frame, consensus_matches()).points, start.T_ref_cur, opt);
    if (consensus.success && consensus.inliers >= config_.min_inliers) {
      start.T_ref_cur = consensus.T_ref_cur;
      opt.gate_at_start = true;
    }
  }
  return guided_match(frame, start.T_ref_cur, std::max(4.0, config_.search_radius_px * 0.5));
}

VoEstimate StereoVisualOdometry::accept(const StereoFrameFeatures& frame, double timestamp,
                                        TrackedPoints tracked, const PoseRefinementResult& res) {
  estimate_noise(tracked.points, tracked.octaves, res);
  VoEstimate e;
  e.status = VoStatus::kTracked;
  e.relative_pose = T_ref_prev_.inverse() * res.T_ref_cur;
  e.covariance = res.covariance;
  e.inliers = res.inliers;
  e.previous_measurement.assign(frame.measurements.size(), -1);
  for (std::size_t i = 0; i < tracked.points.size(); ++i) {
    if (res.inlier[i] && tracked.cur[i] >= 0)
      e.previous_measurement[static_cast<std::size_t>(tracked.cur[i])] = tracked.ref[i];
  }
  // kept for excluding()
  last_tracked_ = std::move(tracked.points);
  last_tracked_current_ = std::move(tracked.cur);
  last_T_ref_cur_ = res.T_ref_cur;
  last_T_ref_prev_ = T_ref_prev_;
  velocity_ = e.relative_pose;
  const double dt = timestamp - previous_time_;
  velocity_dt_ = std::isfinite(dt) && dt > 0.0 ? dt : std::nan("");
  previous_time_ = timestamp;
  velocity_known_ = true;
  last_covariance_ = e.covariance;
  set_reference(frame);
  return e;
}

StereoVisualOdometry::TrackedPoints StereoVisualOdometry::tracked_points(
    const StereoFrameFeatures& frame, const std::vector<Match>& matches) const {
  TrackedPoints set;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    const StereoMeasurement& r = ref_.measurements[static_cast<std::size_t>(matches[i].ref)];
    const cv::KeyPoint& kp = frame.left.keypoints[static_cast<std::size_t>(matches[i].cur)];
    TrackedPoint t;
    t.point_ref = r.point;
    t.z_ref = r.z;
    t.sigma_ref = r.pixel_sigma;
    const int mi = frame.left_to_measurement.empty()
                       ? -1
                       : frame.left_to_measurement[static_cast<std::size_t>(matches[i].cur)];
    if (mi >= 0) {
      const StereoMeasurement& c = frame.measurements[static_cast<std::size_t>(mi)];
      t.z_cur = c.z;
      t.sigma_cur = c.pixel_sigma;
      t.cur_stereo = true;
    } else {
      t.z_cur = Eigen::Vector3d(kp.pt.x, kp.pt.y, 0.0);
      t.sigma_cur = r.pixel_sigma / scales_[static_cast<std::size_t>(r.octave)] *
                    scales_[static_cast<std::size_t>(kp.octave)];
      t.cur_stereo = false;
    }
    set.points.push_back(t);
    set.ref.push_back(matches[i].ref);
    set.cur.push_back(mi);
    set.octaves.push_back(std::max(r.octave, kp.octave));
  }
  return set;
}

VoEstimate StereoVisualOdometry::excluding(const VoEstimate& full, const std::vector<char>& excluded) const {
  if (full.status != VoStatus::kTracked || last_tracked_.empty()) return full;
  std::vector<TrackedPoint> kept;
  kept.reserve(last_tracked_.size());
  for (std::size_t i = 0; i < last_tracked_.size(); ++i) {
    const int cur = last_tracked_current_[i];
    if (cur >= 0 && static_cast<std::size_t>(cur) < excluded.size() &&
        excluded[static_cast<std::size_t>(cur)])
      continue;
    kept.push_back(last_tracked_[i]);
  }
  if (static_cast<int>(kept.size()) < std::max(config_.min_inliers, 8)) return full;
  const PoseRefinementResult res =
      refine_stereo_pose(camera_, kept, last_T_ref_cur_, pose_refinement_options(config_));
  if (!res.success || res.inliers < config_.min_inliers) return full;
  VoEstimate e = full;
  e.relative_pose = last_T_ref_prev_.inverse() * res.T_ref_cur;
  e.covariance = res.covariance;
  e.inliers = res.inliers;
  return e;
}

}  // namespace glmbslam::frontend
