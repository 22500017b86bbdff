#include "app/victoria_park_ml.hpp"

#include <string>

#include <spdlog/spdlog.h>

#include "backend/mlslam/rfs_ml_slam.hpp"
#include "core/progress.hpp"

namespace glmbslam::app {

backend::MlSlamReport solve_victoria_park_ml(const backend::AckermannMotion& motion,
                                             const backend::VictoriaParkMeasurement& model,
                                             const backend::MlSlamConfig& config,
                                             const Eigen::Vector3d& initial_pose,
                                             const std::vector<backend::AckermannMotion::Control>& controls,
                                             const std::vector<VpMeasurementSet>& measurements,
                                             bool standalone, const std::function<bool()>& stop,
                                             VpPoseList& poses, std::vector<Eigen::Vector2d>& map) {
  using Slam = backend::RfsMlSlam<backend::AckermannMotion, backend::VictoriaParkMeasurement>;
  // step 0 is the initial pose without a scan; the control of step 0 is never used
  Slam::ControlList u{backend::AckermannMotion::Control::Zero(3, 0)};
  u.insert(u.end(), controls.begin(), controls.end());
  std::vector<Slam::MeasurementSet> Z{Slam::MeasurementSet{}};
  Z.insert(Z.end(), measurements.begin(), measurements.end());
  Slam::PoseList x;
  Slam::LandmarkList m(map.begin(), map.end());
  Slam slam(motion, model, config);
  slam.set_stop(stop);
  backend::MlSlamReport r;
  if (standalone) {
    ProgressReporter progress(Z.size(), "mlslam");
    slam.set_progress([&](std::size_t done, std::size_t, std::size_t landmarks) {
      progress.update(done, "landmarks " + std::to_string(landmarks));
    });
    r = slam.solve_from_odometry(initial_pose, u, Z, x, m);
    progress.finish_at(x.size());
  } else {
    x.push_back(initial_pose);
    x.insert(x.end(), poses.begin(), poses.end());
    r = slam.solve(x, u, Z, m);
  }
  for (std::size_t i = 0; i < r.log_likelihood_per_round.size(); ++i)
    spdlog::debug("RFS-ML: round {}: log-likelihood {:.3f}", i + 1, r.log_likelihood_per_round[i]);
  spdlog::info(
      "RFS-ML: {} rounds, log-likelihood {:.1f} -> {:.1f}, {} births, {} deaths, {} merges, motion noise "
      "scale {:.4f}, {:.1f} s",
      r.rounds, r.initial_log_likelihood, r.final_log_likelihood, r.births, r.deaths, r.merges,
      r.motion_scale, r.ms / 1000.0);
  if (r.stopped)
    spdlog::warn("RFS-ML: interrupted after {} rounds; keeping the estimate of the last one", r.rounds);
  poses.assign(x.begin() + 1, x.end());
  map.assign(m.begin(), m.end());
  return r;
}

}  // namespace glmbslam::app
