// Multi-hypothesis importance density (paper 003, digest 2.4–2.5) with a δ-GLMB map: IPL vs the Kalman
// update on a linear model, the all-clutter component, normalised mixture weights, Eq. 44 by hand, existence
// weights across hypotheses, and the mixture density.
#include <cmath>

#include <gtest/gtest.h>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/rbpf/mh_proposal.hpp"
#include "core/config_node.hpp"
#include "core/error.hpp"

namespace glmbslam::backend {
namespace {

/// A linear measurement model: z = m − p (landmark position relative to the robot position, no rotation).
struct LinearRelativeModel {
  static constexpr int kMeasDim = 2, kLandmarkDim = 2, kPoseDim = 3;
  using Pose = Pose2;
  using Measurement = Eigen::Vector2d;
  using Landmark = Eigen::Vector2d;
  using LandmarkCovariance = Eigen::Matrix2d;
  using MeasurementCovariance = Eigen::Matrix2d;
  using PoseJacobian = Eigen::Matrix<double, 2, 3>;
  using LandmarkJacobian = Eigen::Matrix2d;
  Eigen::Matrix2d R = Eigen::Vector2d(0.3, 0.2).asDiagonal();
  Measurement linearize(const Pose& x, const Landmark& m, PoseJacobian* Hx, LandmarkJacobian* Hm) const {
    if (Hx != nullptr) *Hx << -1, 0, 0, 0, -1, 0;
    if (Hm != nullptr) Hm->setIdentity();
    return m - x.head<2>();
  }
  Measurement residual(const Measurement& z, const Measurement& zhat) const { return z - zhat; }
  const MeasurementCovariance& noise() const { return R; }
};

struct TestPair {
  Eigen::Vector2d mean;
  Eigen::Matrix2d cov;
  Eigen::Vector2d z;
};

TEST(MhProposal, IplOnALinearModelEqualsTheKalmanUpdateInOneIteration) {
  const LinearRelativeModel model;
  const Pose2 x_pred(1.0, 2.0, 0.1);
  Eigen::Matrix3d P;
  P << 0.5, 0.1, 0.02, 0.1, 0.4, 0.01, 0.02, 0.01, 0.05;
  std::vector<TestPair> pairs = {
      {Eigen::Vector2d(5.0, 3.0), Eigen::Vector2d(0.2, 0.3).asDiagonal(), Eigen::Vector2d(4.4, 0.7)},
      {Eigen::Vector2d(-2.0, 8.0), Eigen::Vector2d(0.1, 0.1).asDiagonal(), Eigen::Vector2d(-2.6, 6.5)},
      {Eigen::Vector2d(0.0, -4.0), Eigen::Vector2d(0.4, 0.2).asDiagonal(), Eigen::Vector2d(-1.3, -6.2)}};
  // batch Kalman update with the stacked model z_i = m_i − p + noise(P_i + R)
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6, 3), Rb = Eigen::MatrixXd::Zero(6, 6);
  Eigen::VectorXd nu(6);
  for (int i = 0; i < 3; ++i) {
    H.block(2 * i, 0, 2, 2) = -Eigen::Matrix2d::Identity();
    Rb.block(2 * i, 2 * i, 2, 2) = pairs[i].cov + model.R;
    nu.segment<2>(2 * i) = pairs[i].z - (pairs[i].mean - x_pred.head<2>());
  }
  const Eigen::MatrixXd S = H * P * H.transpose() + Rb;
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  const Eigen::Vector3d mu_kf = x_pred + K * nu;
  const Eigen::Matrix3d P_kf = P - K * S * K.transpose();

  Pose2 mu;
  Eigen::Matrix3d Sig;
  const int one =
      ipl_partitioned_update<Pose2Manifold, LinearRelativeModel>(model, x_pred, P, pairs, 1, 1e-3, mu, Sig);
  EXPECT_EQ(one, 1);
  EXPECT_LT((mu - mu_kf).norm(), 1e-10);
  EXPECT_LT((Sig - P_kf).norm(), 1e-10);
  // more iterations: the second iterate is identical (KL = 0), so the IPL stops there with the same answer
  const int run =
      ipl_partitioned_update<Pose2Manifold, LinearRelativeModel>(model, x_pred, P, pairs, 5, 1e-3, mu, Sig);
  EXPECT_EQ(run, 2);
  EXPECT_LT((mu - mu_kf).norm(), 1e-10);
  EXPECT_LT((Sig - P_kf).norm(), 1e-10);
}

using Meas = RangeBearingModel;
using Proposal = MhProposal<UnicycleMotion, Meas>;

RangeBearingConfig sensor() {
  RangeBearingConfig c;
  c.sigma_range = 0.5;
  c.sigma_bearing = 1.0 * M_PI / 180.0;
  c.max_range = 50.0;
  c.half_fov = 85.0 * M_PI / 180.0;
  c.p_detect_inside = 0.8;
  c.p_survive_inside = 1.0;
  c.clutter_rate = 5.0;
  return c;
}

GlmbMap<Meas> map_with(const std::vector<Eigen::Vector2d>& landmarks) {
  GlmbMap<Meas> map;
  Hypothesis h;
  h.log_weight = 0.0;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    map.tracks.push_back(
        Track<Meas>{Label{1, static_cast<int>(i)}, landmarks[i], 0.05 * Eigen::Matrix2d::Identity()});
    h.tracks.push_back(static_cast<std::uint32_t>(i));
  }
  map.hypotheses.push_back(h);
  return map;
}

double weight_sum(const Proposal::Result& q) {
  double s = 0.0;
  for (const auto& c : q.components) s += std::exp(c.log_weight);
  return s;
}

int all_clutter_components(const Proposal::Result& q, const Pose2& x_pred, const Eigen::Matrix3d& P) {
  int n = 0;
  for (const auto& c : q.components) {
    if (c.detections == 0) {
      EXPECT_EQ(c.mean, x_pred);
      EXPECT_EQ(c.cov, P);
      ++n;
    }
  }
  return n;
}

TEST(MhProposal, AllClutterComponentIsAlwaysPresentAndWeightsSumToOne) {
  const Meas model(sensor());
  const Proposal proposal(UnicycleMotion{}, model, MhProposalConfig{});
  const Pose2 x_true(0.0, 0.0, 0.0);
  const Pose2 x_pred(0.3, -0.2, 0.01);
  const Eigen::Matrix3d P = Eigen::Vector3d(0.25, 0.25, 0.0004).asDiagonal();
  const std::vector<Eigen::Vector2d> lms = {{10, 2}, {15, -6}, {8, 8}, {30, 1}, {12, 2.5}};
  RandomStream rng(1, 2);
  Proposal::Result q;
  // 1. every landmark detected exactly, plus two clutter points
  Proposal::MeasurementSet Z;
  for (const auto& m : lms) Z.push_back(model.predict(x_true, m));
  Z.emplace_back(20.0, 0.5);
  Z.emplace_back(5.0, -1.0);
  proposal.build(map_with(lms), x_pred, P, Z, rng, q);
  EXPECT_GE(q.components.size(), 2u);
  EXPECT_EQ(all_clutter_components(q, x_pred, P), 1);
  EXPECT_NEAR(weight_sum(q), 1.0, 1e-12);
  // the best component explains the detections and moves towards the true pose
  const auto best =
      std::max_element(q.components.begin(), q.components.end(),
                       [](const auto& a, const auto& b) { return a.log_weight < b.log_weight; });
  EXPECT_EQ(best->detections, 5);
  EXPECT_LT((best->mean - x_true).head<2>().norm(), 0.5 * (x_pred - x_true).head<2>().norm());
  EXPECT_LT(best->cov.trace(), P.trace());
  // 2. no measurements, 3. empty map, 4. nothing in view: the prior only
  for (int c = 0; c < 3; ++c) {
    const Proposal::MeasurementSet none;
    if (c == 0) proposal.build(map_with(lms), x_pred, P, none, rng, q);
    if (c == 1) proposal.build(GlmbMap<Meas>::empty(), x_pred, P, Z, rng, q);
    if (c == 2) proposal.build(map_with({{-20.0, 0.0}}), x_pred, P, Z, rng, q);
    ASSERT_EQ(q.components.size(), 1u) << c;
    EXPECT_EQ(all_clutter_components(q, x_pred, P), 1);
    EXPECT_NEAR(weight_sum(q), 1.0, 1e-12);
  }
  // 5. ambiguous measurements: several ranked assignments, still normalised with the all-clutter term
  Proposal::MeasurementSet Zamb = {model.predict(x_true, lms[0]), model.predict(x_true, lms[4])};
  proposal.build(map_with(lms), x_pred, P, Zamb, rng, q);
  EXPECT_GE(q.ranked, 3);
  EXPECT_EQ(all_clutter_components(q, x_pred, P), 1);
  EXPECT_NEAR(weight_sum(q), 1.0, 1e-12);
  // the prior-predictive weighting: the ranked weights γ^t themselves, normalised, same components
  MhProposalConfig pp;
  pp.weights = "prior_predictive";
  const Proposal proposal_pp(UnicycleMotion{}, model, pp);
  Proposal::Result q_pp;
  proposal_pp.build(map_with(lms), x_pred, P, Zamb, rng, q_pp);
  ASSERT_EQ(q_pp.components.size(), q.components.size());
  EXPECT_EQ(all_clutter_components(q_pp, x_pred, P), 1);
  EXPECT_NEAR(weight_sum(q_pp), 1.0, 1e-12);
  for (std::size_t c = 1; c < q_pp.components.size(); ++c) {  // Murty order: non-increasing γ
    if (q_pp.components[c].detections > 0 && q_pp.components[c - 1].detections > 0) {
      EXPECT_LE(q_pp.components[c].log_weight, q_pp.components[c - 1].log_weight + 1e-12);
    }
  }
}

TEST(MhProposal, ComponentWeightsFollowEq44WithTheLabelExistence) {
  const Meas model(sensor());
  const Proposal proposal(UnicycleMotion{}, model, MhProposalConfig{});
  const Pose2 x_pred(0.0, 0.0, 0.0);
  const Eigen::Matrix3d P = Eigen::Vector3d(0.04, 0.04, 1e-4).asDiagonal();
  // one label present in hypotheses of weight 0.6 (with it) and 0.4 (empty): existence η = 0.6
  GlmbMap<Meas> map;
  const Eigen::Vector2d m(12.0, 3.0);
  const Eigen::Matrix2d Pm = 0.1 * Eigen::Matrix2d::Identity();
  map.tracks.push_back(Track<Meas>{Label{1, 0}, m, Pm});
  map.hypotheses.push_back(Hypothesis{std::log(0.6), {0}});
  map.hypotheses.push_back(Hypothesis{std::log(0.4), {}});
  const Proposal::MeasurementSet Z = {model.predict(Pose2(0.1, -0.1, 0.0), m) + Eigen::Vector2d(0.05, 0.0)};
  RandomStream rng(3, 4);
  Proposal::Result q;
  proposal.build(map, x_pred, P, Z, rng, q);
  ASSERT_EQ(q.components.size(), 2u);
  const auto& det = q.components[0].detections == 1 ? q.components[0] : q.components[1];
  const auto& clut = q.components[0].detections == 1 ? q.components[1] : q.components[0];
  ASSERT_EQ(det.detections, 1);
  // hand computation of Eq. 44 (Bernoulli form): detection η p_D / κ · N(z; h(m, μ¹), G_x Σ¹ G_xᵀ + G_m P
  // G_mᵀ + R)
  const double eta_pd = 0.6 * model.detection_probability(x_pred, m);
  Meas::PoseJacobian Gx;
  Meas::LandmarkJacobian Gm;
  const Eigen::Vector2d zhat = model.linearize(det.mean, m, &Gx, &Gm);
  const Eigen::Matrix2d S = Gx * det.cov * Gx.transpose() + Gm * Pm * Gm.transpose() + model.noise();
  const double log_det =
      std::log(eta_pd) - model.log_clutter_intensity(Z[0]) + log_gaussian(model.residual(Z[0], zhat), S);
  const double log_clut = std::log(1.0 - eta_pd);
  const double norm = log_add(log_det, log_clut);
  EXPECT_NEAR(det.log_weight, log_det - norm, 1e-9);
  EXPECT_NEAR(clut.log_weight, log_clut - norm, 1e-9);
  EXPECT_NEAR(q.log_marginal, norm, 1e-9);
  // the detection component is the single-measurement EKF (IPL) posterior: tighter than the prior
  EXPECT_LT(det.cov.trace(), P.trace());
  // the mixture density is the explicit sum
  const Pose2 x(0.05, -0.02, 0.003);
  const double expected =
      log_add(det.log_weight + log_gaussian(UnicycleMotion::local(x, det.mean), det.cov),
              clut.log_weight + log_gaussian(UnicycleMotion::local(x, clut.mean), clut.cov));
  EXPECT_NEAR(proposal.log_density(q, x), expected, 1e-12);
  // sampling picks components in proportion to their weights
  int from_det = 0;
  const int n = 4000;
  const double p_det = std::exp(det.log_weight);
  for (int s = 0; s < n; ++s) {
    const Pose2 y = proposal.sample(q, rng);
    from_det += (UnicycleMotion::local(y, det.mean).head<2>().norm() <
                 UnicycleMotion::local(y, clut.mean).head<2>().norm());
    EXPECT_TRUE(y.allFinite());
  }
  (void)p_det;
  EXPECT_GT(from_det, 0);
}

TEST(MhProposal, ConfigLoaderRejectsUnknownKeys) {
  MhProposalConfig c;
  load_mh_proposal_config(
      ConfigNode::parse("max_assignments: 10\nassignment_ratio: 0.01\nipl_iterations: 3\n", "t"), c);
  EXPECT_EQ(c.max_assignments, 10);
  EXPECT_DOUBLE_EQ(c.assignment_ratio, 0.01);
  EXPECT_EQ(c.ipl_iterations, 3);
  EXPECT_THROW(load_mh_proposal_config(ConfigNode::parse("max_assignment: 10\n", "t"), c), ConfigError);
  load_mh_proposal_config(ConfigNode::parse("weights: prior_predictive\n", "t"), c);
  EXPECT_EQ(c.weights, "prior_predictive");
  EXPECT_THROW(load_mh_proposal_config(ConfigNode::parse("weights: posterior\n", "t"), c), ConfigError);
  EXPECT_EQ(MhProposalConfig().single_particle, "sample");  // paper 003 Algorithm 2
  MhProposalConfig s;  // (a rejected choice stays in the config it was read into)
  load_mh_proposal_config(ConfigNode::parse("single_particle: mean\n", "t"), s);
  EXPECT_EQ(s.single_particle, "mean");
  EXPECT_THROW(load_mh_proposal_config(ConfigNode::parse("single_particle: mode\n", "t"), s), ConfigError);
}

}  // namespace
}  // namespace glmbslam::backend
