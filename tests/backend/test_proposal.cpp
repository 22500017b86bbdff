// Optimal-kernel proposal: with a well-known map, the proposal concentrates at the true pose; with no map it
// is the motion prior. With the birth candidates as extra rows (rbpf.proposal_births), on an empty map whose
// birth candidates come from a scan at a known previous pose, the proposal is pulled to the pose the new scan
// implies (one birth: exactly the mixture of "not born", "born and missed" and the EKF step of "born and
// detected", weighted by the update's η); with "never" it is the motion prior, and "empty_view" ignores the
// births while a mapped landmark is in view.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "core/error.hpp"

namespace glmbslam::backend {
namespace {

using Proposal = OptimalProposal<UnicycleMotion, RangeBearingModel>;
using Map = GlmbMap<RangeBearingModel>;

const std::vector<Eigen::Vector2d> kLandmarks = {{5, 2}, {3, -4}, {-2, 6}, {8, 8}};

struct Problem {
  RangeBearingConfig sensor;
  UnicycleMotionConfig mc;
  Pose2 x_prev{0.0, 0.0, 0.0};
  Eigen::Vector2d u{1.0, 0.1};
  Pose2 truth, x_pred;
  Eigen::Matrix3d P_pred;
  Problem() {
    sensor.sigma_range = 0.05;
    sensor.sigma_bearing = 0.5 * M_PI / 180.0;
    sensor.max_range = 20.0;
    sensor.half_fov = M_PI;
    sensor.p_detect_inside = 0.9;
    sensor.clutter_rate = 1.0;
    mc.sigma_v = 0.2;
    mc.sigma_omega = 2.0 * M_PI / 180.0;
    const UnicycleMotion motion(mc);
    x_pred = motion.predict(x_prev, u);
    P_pred = motion.process_noise(x_prev, u);
    // the true pose: off the prediction by 1.5 σ in speed and −1 σ in turn rate (≈ 2° of heading)
    truth = motion.predict(x_prev, Eigen::Vector2d(u(0) + 1.5 * mc.sigma_v, u(1) - mc.sigma_omega));
  }
  RangeBearingModel model() const { return RangeBearingModel(sensor); }
  UnicycleMotion motion() const { return UnicycleMotion(mc); }
  /// An empty map whose birth candidates are the landmarks seen (noise-free) from x_prev.
  Map births_from_previous_scan(const std::vector<Eigen::Vector2d>& lms, double r_b) const {
    Map map = Map::empty();
    const RangeBearingModel m = model();
    for (std::size_t i = 0; i < lms.size(); ++i) {
      BirthCandidate<RangeBearingModel> bc;
      bc.label = Label{1, static_cast<int>(i)};
      m.initialize(x_prev, m.predict(x_prev, lms[i]), &bc.mean, &bc.cov);
      bc.log_existence = std::log(r_b);
      map.births.push_back(bc);
    }
    return map;
  }
  Proposal::MeasurementSet scan_at_truth(const std::vector<Eigen::Vector2d>& lms) const {
    Proposal::MeasurementSet z;
    for (const auto& l : lms) z.push_back(model().predict(truth, l));
    return z;
  }
  Proposal::Result build(const Map& map, const Proposal::MeasurementSet& z, const RbpfConfig& c) const {
    const Proposal proposal(motion(), model(), c);
    RandomStream rng(3, 0);
    Proposal::Result q;
    proposal.build(map, x_pred, P_pred, z, rng, q);
    return q;
  }
};

RbpfConfig with_births(const std::string& mode) {
  RbpfConfig c;
  c.proposal_births = mode;
  return c;
}

TEST(OptimalProposal, ConcentratesAtTheTruePoseWithAKnownMap) {
  const Problem p;
  Map map;
  const std::vector<Eigen::Vector2d>& lms = kLandmarks;
  Hypothesis h{0.0, {}};
  for (std::size_t i = 0; i < lms.size(); ++i) {
    map.tracks.push_back(
        Track<RangeBearingModel>{Label{0, static_cast<int>(i)}, lms[i], Eigen::Matrix2d::Identity() * 1e-4});
    h.tracks.push_back(static_cast<std::uint32_t>(i));
  }
  map.hypotheses.push_back(h);
  const Proposal::MeasurementSet z = p.scan_at_truth(lms);
  const Proposal::Result q = p.build(map, z, RbpfConfig());
  // (the state-space Gaussian prior is linearised in the control noise, so its second-order part is not
  // reachable)
  const double prior_error = (p.x_pred - p.truth).head<2>().norm();
  ASSERT_GT(prior_error, 0.2);
  EXPECT_LT((q.mean - p.truth).head<2>().norm(), 0.05 * prior_error);
  EXPECT_LT(std::abs(wrap_angle(q.mean(2) - p.truth(2))), 0.2 * M_PI / 180.0);
  EXPECT_LT(q.cov.trace(), 0.05 * p.P_pred.trace());  // 4 ranges at σ_r = 5 cm vs a 20 cm prior
  // the best association explains every measurement with its landmark
  EXPECT_GT(q.components.front().log_weight, std::log(0.5));
  // with an empty map the proposal is the motion prior
  const Proposal::Result q_empty = p.build(Map::empty(), z, RbpfConfig());
  EXPECT_LT((q_empty.mean - p.x_pred).norm(), 1e-12);
  EXPECT_LT((q_empty.cov - p.P_pred).norm(), 1e-12);
}

TEST(OptimalProposalBirths, OneBirthGivesTheExactMixtureOfItsThreeOutcomes) {
  const Problem p;
  const RangeBearingModel model = p.model();
  const std::vector<Eigen::Vector2d> lms = {{6.0, 3.0}};
  const double r_b = 0.003;
  const Map map = p.births_from_previous_scan(lms, r_b);
  const Proposal::MeasurementSet z = p.scan_at_truth(lms);
  RbpfConfig c = with_births("always");
  c.ipl_iterations = 1;  // one EKF step linearised at x̄: closed form below
  const Proposal::Result q = p.build(map, z, c);

  // the η of a birth in the δ-GLMB update (digest 0.2), with the pose-marginal S' (digest 0.5 step 3)
  const auto& bc = map.births[0];
  RangeBearingModel::PoseJacobian Hx;
  RangeBearingModel::LandmarkJacobian Hm;
  const Eigen::Vector2d zhat = model.linearize(p.x_pred, bc.mean, &Hx, &Hm);
  const Eigen::Matrix2d Omega = Hm * bc.cov * Hm.transpose() + model.noise();
  const Eigen::Matrix2d S = Hx * p.P_pred * Hx.transpose() + Omega;
  const Eigen::Vector2d nu = model.residual(z[0], zhat);
  const double pd = p.sensor.p_detect_inside;
  const double eta_dead = 1.0 - r_b;
  const double eta_missed = r_b * (1.0 - pd);
  const double eta_detected = r_b * pd * std::exp(log_gaussian(nu, S) - model.log_clutter_intensity(z[0]));
  const double total = eta_dead + eta_missed + eta_detected;
  EXPECT_NEAR(q.log_marginal, std::log(total), 1e-9);
  const double w = eta_detected / total;
  ASSERT_GT(w, 0.2);  // all three outcomes matter
  ASSERT_LT(w, 0.8);
  // born and detected: the EKF step of (x̄, P̄) with z (FastSLAM 2.0)
  const Eigen::Matrix<double, 3, 2> K = p.P_pred * Hx.transpose() * S.inverse();
  const Eigen::Vector3d d = K * nu;
  const Eigen::Matrix3d Sigma_det = p.P_pred - K * S * K.transpose();
  // the other two outcomes leave the motion prior; moment match of the three
  const Eigen::Vector3d mean_offset = w * d;
  const Eigen::Matrix3d cov = w * (Sigma_det + (d - mean_offset) * (d - mean_offset).transpose()) +
                              (1.0 - w) * (p.P_pred + mean_offset * mean_offset.transpose());
  EXPECT_LT(UnicycleMotion::local(q.mean, UnicycleMotion::retract(p.x_pred, mean_offset)).norm(), 1e-9);
  EXPECT_LT((q.cov - cov).norm(), 1e-9 * cov.norm());
  ASSERT_EQ(q.components.size(), 3u);  // not born, born and missed, born and detected

  // with the option off: the motion prior, and the marginal of an empty association set
  const Proposal::Result q_never = p.build(map, z, with_births("never"));
  EXPECT_EQ(q_never.mean, p.x_pred);
  EXPECT_EQ(q_never.cov, p.P_pred);
  EXPECT_EQ(q_never.log_marginal, 0.0);
}

TEST(OptimalProposalBirths, BirthsFromAKnownPreviousPosePullTheProposalToTheTruePose) {
  const Problem p;
  const std::vector<Eigen::Vector2d>& lms = kLandmarks;
  const Map map = p.births_from_previous_scan(lms, 5e-3);  // the phdslam3 r_B
  const Proposal::MeasurementSet z = p.scan_at_truth(lms);
  const double prior_error = (p.x_pred - p.truth).head<2>().norm();
  const double prior_heading_error = std::abs(wrap_angle(p.x_pred(2) - p.truth(2)));
  ASSERT_GT(prior_error, 0.2);
  ASSERT_GT(prior_heading_error, 1.5 * M_PI / 180.0);

  for (const char* mode : {"always", "empty_view"}) {  // the map has no track: both use the births
    const Proposal::Result q = p.build(map, z, with_births(mode));
    EXPECT_LT((q.mean - p.truth).head<2>().norm(), 0.1 * prior_error) << mode;
    EXPECT_LT(std::abs(wrap_angle(q.mean(2) - p.truth(2))), 0.1 * prior_heading_error) << mode;
    EXPECT_LT(q.cov.trace(), 0.1 * p.P_pred.trace()) << mode;
  }
  const Proposal::Result q_never = p.build(map, z, with_births("never"));
  EXPECT_EQ(q_never.mean, p.x_pred);
  EXPECT_EQ(q_never.cov, p.P_pred);

  // one mapped landmark in view: "empty_view" ignores the births (= "never"), "always" still uses them
  Map mapped = map;
  mapped.tracks.push_back(
      Track<RangeBearingModel>{Label{0, 0}, Eigen::Vector2d(10.0, -3.0), Eigen::Matrix2d::Identity() * 1e-2});
  mapped.hypotheses[0].tracks.push_back(0);
  const Proposal::Result q_view = p.build(mapped, z, with_births("empty_view"));
  const Proposal::Result q_view_never = p.build(mapped, z, with_births("never"));
  EXPECT_EQ(q_view.mean, q_view_never.mean);
  EXPECT_EQ(q_view.cov, q_view_never.cov);
  const Proposal::Result q_view_always = p.build(mapped, z, with_births("always"));
  EXPECT_LT((q_view_always.mean - p.truth).head<2>().norm(), 0.1 * prior_error);
}

TEST(OptimalProposalBirths, FilterStepOneAfterTheInitialScan) {
  // GlmbSlam with one particle and the proposal mean as its pose: after initial_scan(Z_0) at the known x_0,
  // the pose of step 1 is the motion prediction without the births, close to the truth with them
  const Problem p;
  const std::vector<Eigen::Vector2d>& lms = kLandmarks;
  Proposal::MeasurementSet z0;
  for (const auto& l : lms) z0.push_back(p.model().predict(p.x_prev, l));
  const Proposal::MeasurementSet z1 = p.scan_at_truth(lms);
  for (const char* mode : {"never", "empty_view", "always"}) {
    RbpfConfig c = with_births(mode);
    c.particles = 1;
    c.single_particle = "mean";
    c.glmb.birth_prob_unexplained = 5e-3;
    GlmbSlam<UnicycleMotion, RangeBearingModel> slam(p.motion(), p.model(), c, p.x_prev);
    slam.initial_scan(z0);
    slam.step(p.u, z1);
    if (std::string(mode) == "never") {
      EXPECT_LT((slam.pose() - p.x_pred).norm(), 1e-12);
    } else {
      EXPECT_LT((slam.pose() - p.truth).head<2>().norm(), 0.1 * (p.x_pred - p.truth).head<2>().norm())
          << mode;
    }
  }
}

TEST(OptimalProposalBirths, ConfigKeyIsValidated) {
  EXPECT_EQ(RbpfConfig().proposal_births, "never");  // paper 000: the proposal uses the mapped tracks only
  RbpfConfig c;
  load_rbpf_config(ConfigNode::parse("proposal_births: empty_view\n", "t"), c);
  EXPECT_EQ(c.proposal_births, "empty_view");
  EXPECT_THROW(load_rbpf_config(ConfigNode::parse("proposal_births: sometimes\n", "t"), c), ConfigError);
  const Problem p;
  EXPECT_THROW(Proposal(p.motion(), p.model(), with_births("yes")), ConfigError);
  using Slam = GlmbSlam<UnicycleMotion, RangeBearingModel>;
  EXPECT_THROW(Slam(p.motion(), p.model(), with_births("yes"), p.x_prev), ConfigError);
}

}  // namespace
}  // namespace glmbslam::backend
