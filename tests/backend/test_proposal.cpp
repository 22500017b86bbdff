// Optimal-kernel proposal: with a well-known map, the proposal concentrates at the true pose; with no map it
// is the motion prior.
#include <gtest/gtest.h>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/rbpf/optimal_proposal.hpp"

namespace glmbslam::backend {
namespace {

using Proposal = OptimalProposal<UnicycleMotion, RangeBearingModel>;

TEST(OptimalProposal, ConcentratesAtTheTruePoseWithAKnownMap) {
  RangeBearingConfig sensor;
  sensor.sigma_range = 0.05;
  sensor.sigma_bearing = 0.5 * M_PI / 180.0;
  sensor.max_range = 20.0;
  sensor.half_fov = M_PI;
  sensor.p_detect_inside = 0.9;
  sensor.clutter_rate = 1.0;
  const RangeBearingModel model(sensor);
  UnicycleMotionConfig mc;
  mc.sigma_v = 0.2;
  mc.sigma_omega = 2.0 * M_PI / 180.0;
  const UnicycleMotion motion(mc);
  GlmbMap<RangeBearingModel> map;
  const std::vector<Eigen::Vector2d> lms = {{5, 2}, {3, -4}, {-2, 6}, {8, 8}};
  Hypothesis h{0.0, {}};
  for (std::size_t i = 0; i < lms.size(); ++i) {
    map.tracks.push_back(
        Track<RangeBearingModel>{Label{0, static_cast<int>(i)}, lms[i], Eigen::Matrix2d::Identity() * 1e-4});
    h.tracks.push_back(static_cast<std::uint32_t>(i));
  }
  map.hypotheses.push_back(h);
  const Pose2 x_prev(0, 0, 0);
  const Eigen::Vector2d u(1.0, 0.1);
  const Pose2 x_pred = motion.predict(x_prev, u);
  const Eigen::Matrix3d P_pred = motion.process_noise(x_prev, u);
  // the true pose: 1.5 σ off the prediction along the speed direction
  const Pose2 truth =
      motion.predict(x_prev, Eigen::Vector2d(1.0 + 1.5 * mc.sigma_v, 0.1 - 1.0 * mc.sigma_omega));
  Proposal::MeasurementSet z;
  for (const auto& m : lms) z.push_back(model.predict(truth, m));
  RbpfConfig config;
  const Proposal proposal(motion, model, config);
  RandomStream rng(1, 0);
  Proposal::Result q;
  proposal.build(map, x_pred, P_pred, z, rng, q);
  // (the state-space Gaussian prior is linearised in the control noise, so its second-order part is not
  // reachable)
  const double prior_error = (x_pred - truth).head<2>().norm();
  ASSERT_GT(prior_error, 0.2);
  EXPECT_LT((q.mean - truth).head<2>().norm(), 0.05 * prior_error);
  EXPECT_LT(std::abs(wrap_angle(q.mean(2) - truth(2))), 0.2 * M_PI / 180.0);
  EXPECT_LT(q.cov.trace(), 0.05 * P_pred.trace());  // 4 ranges at σ_r = 5 cm vs a 20 cm prior
  // the best association explains every measurement with its landmark
  EXPECT_GT(q.components.front().log_weight, std::log(0.5));
  // with an empty map the proposal is the motion prior
  GlmbMap<RangeBearingModel> empty = GlmbMap<RangeBearingModel>::empty();
  proposal.build(empty, x_pred, P_pred, z, rng, q);
  EXPECT_LT((q.mean - x_pred).norm(), 1e-12);
  EXPECT_LT((q.cov - P_pred).norm(), 1e-12);
}

}  // namespace
}  // namespace glmbslam::backend
