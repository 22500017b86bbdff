// rbpf.proposal_scale: the particles draw their pose from the optimal-kernel proposal with every covariance
// scaled by s and weigh the draw by that scaled density; s = 0 takes the mean (of a component drawn by weight
// for a mixture). Checked against the unscaled proposal built from the same random stream (same means, s
// times the covariances), the Gaussian density written out by hand, the sample covariance of many draws, the
// component frequencies of a mixture, and in the filter: with s = 0 every particle's pose is its proposal
// mean, and one particle with single_particle "mean" gives the same trajectory whatever s.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "core/error.hpp"
#include "core/gaussian.hpp"

namespace glmbslam::backend {
namespace {

using Motion = UnicycleMotion;
using Meas = RangeBearingModel;
using Proposal = OptimalProposal<Motion, Meas>;
using Slam = GlmbSlam<Motion, Meas>;

/// Three landmarks known to 1 cm; the scan is taken at a pose off the motion prediction (0.2 m faster,
/// 0.02 rad/s less turn than the control says).
struct ScaleSetup {
  UnicycleMotionConfig mc;
  RangeBearingConfig rc;
  Pose2 x0{0.0, 0.0, 0.0};
  Eigen::Vector2d u{1.0, 0.1};
  std::vector<Eigen::Vector2d> landmarks{{6.0, 1.0}, {2.0, -5.0}, {-3.0, 4.0}};
  GlmbMap<Meas> map;

  ScaleSetup() {
    mc.sigma_v = 0.3;
    mc.sigma_omega = 3.0 * M_PI / 180.0;
    rc.sigma_range = 0.1;
    rc.sigma_bearing = 1.0 * M_PI / 180.0;
    rc.max_range = 30.0;
    rc.half_fov = M_PI;
    rc.p_detect_inside = 0.95;
    rc.clutter_rate = 1.0;
    Hypothesis h{0.0, {}};
    for (std::size_t i = 0; i < landmarks.size(); ++i) {
      map.tracks.push_back(
          Track<Meas>{Label{0, static_cast<int>(i)}, landmarks[i], Eigen::Matrix2d::Identity() * 1e-4});
      h.tracks.push_back(static_cast<std::uint32_t>(i));
    }
    map.hypotheses.push_back(h);
  }
  Proposal::MeasurementSet scan(const Pose2& x) const {
    Proposal::MeasurementSet z;
    for (const auto& l : landmarks) z.push_back(Meas(rc).predict(x, l));
    return z;
  }
  Pose2 truth() const { return Motion(mc).predict(x0, u + Eigen::Vector2d(0.2, -0.02)); }
  RbpfConfig config(double scale, bool mixture) const {
    RbpfConfig c;
    c.proposal_scale = scale;
    c.proposal_mixture = mixture;
    return c;
  }
  Proposal proposal(double scale, bool mixture) const {
    return Proposal(Motion(mc), Meas(rc), config(scale, mixture));
  }
  Proposal::Result build(const Proposal& proposal) const {
    const Motion motion(mc);
    RandomStream rng(7, 0);
    Proposal::Result q;
    proposal.build(map, motion.predict(x0, u), motion.process_noise(x0, u), scan(truth()), rng, q);
    return q;
  }
};

TEST(ParticlesProposalScale, ScalesEveryCovarianceAndKeepsTheMeans) {
  const ScaleSetup s;
  for (bool mixture : {false, true}) {
    const Proposal p1 = s.proposal(1.0, mixture);
    const Proposal ps = s.proposal(0.25, mixture);
    const Proposal::Result q1 = s.build(p1);
    const Proposal::Result qs = s.build(ps);
    ASSERT_EQ(q1.components.size(), qs.components.size());
    EXPECT_EQ((qs.mean - q1.mean).norm(), 0.0);
    EXPECT_LT((qs.cov - 0.25 * q1.cov).norm(), 1e-14 * q1.cov.norm());
    for (std::size_t c = 0; c < q1.components.size(); ++c) {
      EXPECT_EQ(qs.components[c].log_weight, q1.components[c].log_weight);
      EXPECT_EQ((qs.components[c].mean - q1.components[c].mean).norm(), 0.0);
      EXPECT_LT((qs.components[c].cov - 0.25 * q1.components[c].cov).norm(),
                1e-14 * q1.components[c].cov.norm());
    }
    // the proposal is informative: well inside the motion prior
    const Motion motion(s.mc);
    EXPECT_LT(q1.cov.trace(), 0.5 * motion.process_noise(s.x0, s.u).trace());
  }
}

TEST(ParticlesProposalScale, DrawsAndDensityAreThoseOfTheScaledGaussian) {
  const ScaleSetup s;
  const Proposal ps = s.proposal(0.25, false);
  const Proposal::Result qs = s.build(ps);
  const Eigen::Matrix3d expected = 0.25 * s.build(s.proposal(1.0, false)).cov;
  RandomStream rng(11, 0);
  const int n = 20000;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Pose2 x = ps.sample(qs, rng);
    const Eigen::Vector3d d = Motion::local(x, qs.mean);
    sum += d;
    scatter += d * d.transpose();
    if (i < 5) {  // the density: N(x ⊖ μ; 0, s Σ) written out
      EXPECT_NEAR(
          ps.log_density(qs, x),
          -0.5 * d.dot(expected.inverse() * d) - 0.5 * std::log((2.0 * M_PI * expected).determinant()), 1e-9);
    }
  }
  const Eigen::Matrix3d cov = scatter / n;
  // sample variances within 4 standard errors (relative s.e. of a variance: sqrt(2/n) = 1 %)
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(cov(i, i) / expected(i, i), 1.0, 4.0 * std::sqrt(2.0 / n)) << i;
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(sum(i) / n), 4.0 * std::sqrt(expected(i, i) / n)) << i;
}

TEST(ParticlesProposalScale, ZeroDrawsTheMeanWeighedByTheUnscaledDensity) {
  const ScaleSetup s;
  const Proposal::Result q1 = s.build(s.proposal(1.0, false));
  const Proposal p0 = s.proposal(0.0, false);
  const Proposal::Result q0 = s.build(p0);
  EXPECT_EQ((q0.cov - q1.cov).norm(), 0.0);
  RandomStream rng(5, 0);
  for (int i = 0; i < 10; ++i) EXPECT_EQ((p0.sample(q0, rng) - q0.mean).norm(), 0.0);
  // the weight's q(x) at the mean: the Laplace normaliser 1 / sqrt(det(2π Σ))
  EXPECT_NEAR(p0.log_density(q0, q0.mean), -0.5 * std::log((2.0 * M_PI * q1.cov).determinant()), 1e-12);
  // a mixture: the mean of a component drawn by its weight
  const Proposal m0 = s.proposal(0.0, true);
  const Proposal::Result qm = s.build(m0);
  ASSERT_GT(qm.components.size(), 1u);
  std::vector<int> count(qm.components.size(), 0);
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const Pose2 x = m0.sample(qm, rng);
    std::size_t c = 0;
    while (c < qm.components.size() && (x - qm.components[c].mean).norm() != 0.0) ++c;
    ASSERT_LT(c, qm.components.size()) << "not a component mean";
    ++count[c];
  }
  for (std::size_t c = 0; c < qm.components.size(); ++c) {
    const double w = std::exp(qm.components[c].log_weight);
    EXPECT_NEAR(count[c] / static_cast<double>(n), w, 4.0 * std::sqrt(w * (1.0 - w) / n) + 1e-12) << c;
  }
}

/// Runs the filter from x0 over three steps of the control u, scanning the landmarks at the true poses.
void run_three_steps(Slam& slam, const ScaleSetup& s) {
  const Motion motion(s.mc);
  slam.initial_scan(s.scan(s.x0));
  Pose2 truth = s.x0;
  for (int k = 1; k <= 3; ++k) {
    truth = motion.predict(truth, s.u + Eigen::Vector2d(0.1, -0.01));
    slam.step(s.u, s.scan(truth));
  }
}

TEST(ParticlesProposalScale, ZeroMakesEveryParticlePoseItsProposalMean) {
  const ScaleSetup s;
  for (double scale : {0.0, 1.0}) {
    RbpfConfig c = s.config(scale, false);
    c.particles = 5;
    c.glmb.birth_prob_unexplained = 5e-3;
    Slam slam(Motion(s.mc), Meas(s.rc), c, s.x0);
    run_three_steps(slam, s);
    double largest_gap = 0.0;  // between a particle's sampled pose and its proposal mean, over its history
    for (const auto& p : slam.particles()) {
      const auto poses = p.trajectory->poses();
      const auto means = p.trajectory->estimates();
      ASSERT_EQ(poses.size(), 4u);
      for (std::size_t k = 0; k < poses.size(); ++k)
        largest_gap = std::max(largest_gap, (poses[k] - means[k]).norm());
    }
    if (scale == 0.0)
      EXPECT_EQ(largest_gap, 0.0);
    else
      EXPECT_GT(largest_gap, 1e-3);  // the draws of paper 000
  }
}

TEST(ParticlesProposalScale, OneParticleTakingTheMeanIsUnchanged) {
  const ScaleSetup s;
  std::vector<Slam::PoseList> paths;
  for (double scale : {1.0, 0.25, 0.0}) {
    RbpfConfig c = s.config(scale, false);
    c.particles = 1;
    c.single_particle = "mean";
    c.glmb.birth_prob_unexplained = 5e-3;
    Slam slam(Motion(s.mc), Meas(s.rc), c, s.x0);
    run_three_steps(slam, s);
    paths.push_back(slam.trajectory());
  }
  for (std::size_t i = 1; i < paths.size(); ++i) {
    ASSERT_EQ(paths[i].size(), paths[0].size());
    for (std::size_t k = 0; k < paths[0].size(); ++k) EXPECT_EQ((paths[i][k] - paths[0][k]).norm(), 0.0);
  }
}

TEST(ParticlesProposalScale, ConfigKeyIsValidated) {
  EXPECT_EQ(RbpfConfig().proposal_scale, 1.0);  // paper 000: draw from the proposal itself
  RbpfConfig c;
  load_rbpf_config(ConfigNode::parse("proposal_scale: 0.25\n", "t"), c);
  EXPECT_EQ(c.proposal_scale, 0.25);
  load_rbpf_config(ConfigNode::parse("proposal_scale: 0\n", "t"), c);
  EXPECT_EQ(c.proposal_scale, 0.0);
  EXPECT_THROW(load_rbpf_config(ConfigNode::parse("proposal_scale: -0.1\n", "t"), c), ConfigError);
  EXPECT_THROW(load_rbpf_config(ConfigNode::parse("proposal_scale: 1.5\n", "t"), c), ConfigError);
  EXPECT_THROW(load_rbpf_config(ConfigNode::parse("proposal_scale: wide\n", "t"), c), ConfigError);
  const ScaleSetup s;
  for (double bad : {-1.0, 2.0, std::nan("")})
    EXPECT_THROW(Slam(Motion(s.mc), Meas(s.rc), s.config(bad, false), s.x0), ConfigError) << bad;
}

}  // namespace
}  // namespace glmbslam::backend
