// A wide motion prior must widen the proposal's search, not let the pose wander: a still stereo camera
// (KITTI 00-02 calibration) sees 200 static landmarks at 5–40 m, each detected with probability 0.9 and
// 1 px noise, plus 5 clutter points a frame, and the control says "no motion" with a 0.5 m / 0.02 rad
// standard deviation (a constant-velocity fallback's floor). Under that prior every landmark gates with
// several measurements; the proposal's round 0 (pose-marginal S', landmarks scored independently) picks a
// hypothesis of which about half the pairs are wrong. The association rounds of optimal_proposal.hpp
// re-associate at the pose the best hypothesis implies, so the map pins the pose.
#include <gtest/gtest.h>

#include <vector>

#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "core/lie.hpp"
#include "core/random.hpp"
#include "stereo_test_support.hpp"

namespace glmbslam::backend {
namespace {

using Model = StereoMeasurementModel;
using Slam = GlmbSlam<Se3Motion, Model>;
using Proposal = OptimalProposal<Se3Motion, Model>;
using Z = Slam::MeasurementSet;

constexpr double kSigmaT = 0.5;   // m
constexpr double kSigmaR = 0.02;  // rad

/// The stereo settings of config/kitti00-02.yaml.
Model kitti_model() {
  StereoMeasurementConfig c;
  c.pixel_sigma = 1.0;
  c.min_depth = 1.0;
  c.max_depth = 80.0;
  c.p_detect_inside = 0.7;
  c.p_survive_inside = 0.95;
  c.clutter_rate = 10.0;
  return Model(test::kitti_calibration(), c);
}

/// The filter settings of config/kitti00-02.yaml (one particle, its proposal mean).
RbpfConfig kitti_rbpf(int rounds) {
  RbpfConfig c;
  c.particles = 1;
  c.seed = 0;
  c.single_particle = "mean";
  c.proposal_hypotheses = 2;
  c.proposal_gibbs_samples = 20;
  c.proposal_association_rounds = rounds;
  c.glmb.gate_threshold = 16.27;
  c.glmb.gibbs_samples = 60;
  c.glmb.max_hypotheses = 30;
  c.glmb.birth_prob_unexplained = 1e-4;
  c.glmb.birth_prob_explained = 5e-5;
  c.glmb.freeze_margin = 5.0;
  return c;
}

/// 200 landmarks spread over the image at depths 5–40 m in front of the camera at the identity.
std::vector<Eigen::Vector3d> landmarks(const Model& model) {
  RandomStream rng(100, 0);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 200; ++i) {
    const double u = rng.uniform(20, 1220), v = rng.uniform(20, 356), depth = rng.uniform(5, 40);
    out.push_back(model.camera().triangulate(Eigen::Vector3d(u, v, u - model.camera().bf() / depth)));
  }
  return out;
}

/// The scan of frame k from the identity: each landmark with probability 0.9, 1 px noise, 5 clutter points.
Z scan(const Model& model, const std::vector<Eigen::Vector3d>& lms, int k) {
  RandomStream rng(200, static_cast<std::uint64_t>(k));
  Z z;
  for (const auto& m : lms) {
    if (rng.uniform() > 0.9) continue;
    z.push_back(model.predict(Pose3::Identity(), m) +
                rng.gaussian<3>(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity()));
  }
  for (int c = 0; c < 5; ++c) {
    const double u = rng.uniform(0, 1241), v = rng.uniform(0, 376), disparity = rng.uniform(5, 100);
    z.push_back(Eigen::Vector3d(u, v, u - disparity));
  }
  return z;
}

RelativePoseControl still_control() {
  RelativePoseControl u;
  u.delta = Pose3::Identity();
  u.covariance.setZero();
  u.covariance.diagonal() << kSigmaT * kSigmaT, kSigmaT * kSigmaT, kSigmaT * kSigmaT, kSigmaR * kSigmaR,
      kSigmaR * kSigmaR, kSigmaR * kSigmaR;
  return u;
}

/// Largest distance from the start over `steps` filter steps (the Rao–Blackwellised estimates).
double worst_drift(int rounds, int steps, std::size_t* final_landmarks) {
  const Model model = kitti_model();
  const std::vector<Eigen::Vector3d> lms = landmarks(model);
  Slam slam(Se3Motion(), model, kitti_rbpf(rounds), Pose3::Identity());
  slam.initial_scan(scan(model, lms, 0));
  double worst = 0.0;
  for (int k = 1; k <= steps; ++k) {
    slam.step(still_control(), scan(model, lms, k));
    worst = std::max(worst, slam.estimated_trajectory().back().translation().norm());
  }
  *final_landmarks = slam.landmarks().size();
  return worst;
}

// One proposal with the landmarks known to 1 cm: the mean lands within 1 cm of the true pose (which is the
// prediction itself) although the prior allows half a metre; scored one landmark at a time (round 0 only) the
// same scan pulls it 5 cm away.
TEST(WidePriorProposal, KnownMapPinsThePose) {
  const Model model = kitti_model();
  const std::vector<Eigen::Vector3d> lms = landmarks(model);
  GlmbMap<Model> map;
  Hypothesis h{0.0, {}};
  for (std::size_t i = 0; i < lms.size(); ++i) {
    map.tracks.push_back(
        Track<Model>{Label{0, static_cast<int>(i)}, lms[i], Eigen::Matrix3d::Identity() * 1e-4});
    h.tracks.push_back(static_cast<std::uint32_t>(i));
  }
  map.hypotheses.push_back(h);
  const Se3Motion motion;
  const Pose3 x_pred = Pose3::Identity();
  const Matrix6d P_pred = motion.process_noise(x_pred, still_control());
  auto error = [&](int rounds) {
    const Proposal proposal(motion, model, kitti_rbpf(rounds));
    RandomStream rng(3, 0);
    Proposal::Result q;
    proposal.build(map, x_pred, P_pred, scan(model, lms, 1), rng, q);
    return q.mean.translation().norm();
  };
  EXPECT_LT(error(3), 0.01);
  EXPECT_GT(error(1), 0.03);
}

// Thirty frames of the still camera under the wide prior: the SLAM stays within 2 cm of the start (as with
// a 1 mm prior) and keeps about one landmark per scene point; round 0 alone wanders by decimetres.
TEST(WidePriorProposal, StillCameraUnderAWidePriorStaysPut) {
  std::size_t landmarks_fixed = 0, landmarks_round0 = 0;
  EXPECT_LT(worst_drift(3, 30, &landmarks_fixed), 0.02);
  EXPECT_LE(landmarks_fixed, 210u);
  EXPECT_GT(worst_drift(1, 30, &landmarks_round0), 0.2);
}

}  // namespace
}  // namespace glmbslam::backend
