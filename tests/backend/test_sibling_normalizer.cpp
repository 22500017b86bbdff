// rbpf.particle_normalizer "sibling_mean": the children of one parent update the same map with the same
// measurements (and, at proposal_scale 0, from the same pose), so the exact normaliser G is the same for all
// of them and the differences between their sampled Ĝ are the Gibbs sampler's coverage alone. Their
// log-mean-exp replaces each child's own. Checked on hand-made weights (groups, non-finite children) and in
// the filter: at step 1 every particle is a child of the initial pose, and in a cluttered scene the sampled Ĝ
// spreads the weights of identical particles where the pooled one does not.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "backend/rbpf/labelled_map_filter.hpp"
#include "backend/rbpf/trajectory.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"

namespace glmbslam::backend {
namespace {

/// A child: its log weight and a trajectory node whose parent tells its siblings.
struct Child {
  using Node = TrajectoryNode<double>;
  double log_weight = 0.0;
  std::shared_ptr<const Node> trajectory;
};

/// Children of the given parents, with the given log weights.
std::vector<Child> children(const std::vector<std::shared_ptr<const Child::Node>>& parents,
                            const std::vector<double>& log_weights) {
  std::vector<Child> next(parents.size());
  for (std::size_t i = 0; i < next.size(); ++i) {
    next[i].log_weight = log_weights[i];
    next[i].trajectory = std::make_shared<const Child::Node>(0.0, 1, parents[i]);
  }
  return next;
}

TEST(SiblingNormalizer, ChildrenOfOneParentShareTheLogMeanExpOfTheirFactors) {
  const auto a = std::make_shared<const Child::Node>(0.0, 0, nullptr);  // two parents
  const auto b = std::make_shared<const Child::Node>(0.0, 0, nullptr);
  const std::vector<double> map_log{-3.0, -1.0, 5.0, -2.0, 7.0, kLogZero};
  const std::vector<double> other{0.1, 0.2, 0.3, 0.4, 0.5, 0.6};  // parent weight + log f − log q
  std::vector<double> log_weights(map_log.size());
  for (std::size_t i = 0; i < log_weights.size(); ++i) log_weights[i] = other[i] + map_log[i];
  log_weights[5] = kLogZero;
  std::vector<Child> next = children({a, a, b, a, b, b}, log_weights);
  std::vector<double> scratch;
  pool_sibling_normalizers(map_log, next, scratch);
  const double pooled_a = std::log((std::exp(-3.0) + std::exp(-1.0) + std::exp(-2.0)) / 3.0);
  const double pooled_b = std::log((std::exp(5.0) + std::exp(7.0)) / 2.0);
  EXPECT_NEAR(next[0].log_weight, other[0] + pooled_a, 1e-12);
  EXPECT_NEAR(next[1].log_weight, other[1] + pooled_a, 1e-12);
  EXPECT_NEAR(next[3].log_weight, other[3] + pooled_a, 1e-12);
  EXPECT_NEAR(next[2].log_weight, other[2] + pooled_b, 1e-12);
  EXPECT_NEAR(next[4].log_weight, other[4] + pooled_b, 1e-12);
  EXPECT_EQ(next[5].log_weight, kLogZero);  // a failed child stays failed and is not averaged in
}

TEST(SiblingNormalizer, AnOnlyChildKeepsItsOwnFactor) {
  const auto a = std::make_shared<const Child::Node>(0.0, 0, nullptr);
  const auto b = std::make_shared<const Child::Node>(0.0, 0, nullptr);
  const std::vector<double> map_log{-4.0, 2.5};
  std::vector<Child> next = children({a, b}, {1.0 - 4.0, 2.0 + 2.5});
  std::vector<double> scratch;
  pool_sibling_normalizers(map_log, next, scratch);
  EXPECT_DOUBLE_EQ(next[0].log_weight, -3.0);
  EXPECT_DOUBLE_EQ(next[1].log_weight, 4.5);
}

using Motion = UnicycleMotion;
using Meas = RangeBearingModel;
using Slam = GlmbSlam<Motion, Meas>;

/// Landmarks in pairs 0.5 m apart with clutter between them: many association hypotheses of similar weight,
/// so that each child's update sampler finds a different share of them.
struct ClutteredScene {
  UnicycleMotionConfig mc;
  RangeBearingConfig rc;
  Pose2 x0{0.0, 0.0, 0.0};
  Eigen::Vector2d u{1.0, 0.0};
  std::vector<Eigen::Vector2d> landmarks;

  ClutteredScene() {
    mc.sigma_v = 0.05;
    mc.sigma_omega = 0.5 * M_PI / 180.0;
    rc.sigma_range = 0.3;
    rc.sigma_bearing = 3.0 * M_PI / 180.0;
    rc.max_range = 30.0;
    rc.half_fov = M_PI;
    rc.p_detect_inside = 0.9;
    rc.clutter_rate = 5.0;
    for (int i = 0; i < 20; ++i) {
      const double a = 2.0 * M_PI * i / 20.0;
      landmarks.emplace_back(8.0 * std::cos(a), 8.0 * std::sin(a));
      landmarks.emplace_back(8.25 * std::cos(a + 0.01), 8.25 * std::sin(a + 0.01));
    }
  }
  std::vector<RangeBearingModel::Measurement, Eigen::aligned_allocator<RangeBearingModel::Measurement>> scan(
      const Pose2& x, int clutter_seed) const {
    std::vector<RangeBearingModel::Measurement, Eigen::aligned_allocator<RangeBearingModel::Measurement>> z;
    for (const auto& l : landmarks) z.push_back(Meas(rc).predict(x, l));
    RandomStream rng(static_cast<std::uint64_t>(clutter_seed), 0);
    for (std::size_t i = 0; i < landmarks.size(); i += 2) {  // one false return between each pair
      const Eigen::Vector2d mid =
          0.5 * (landmarks[i] + landmarks[i + 1]) +
          rng.gaussian<2>(Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity() * 0.01);
      z.push_back(Meas(rc).predict(x, mid));
    }
    return z;
  }
  double step1_ess(const std::string& normalizer, int particles) const {
    RbpfConfig c;
    c.particles = particles;
    c.proposal_scale = 0.0;
    c.particle_normalizer = normalizer;
    c.glmb.gibbs_samples = 10;  // few sweeps for many near-equal hypotheses: the coverage differs by child
    Slam slam(Motion(mc), Meas(rc), c, x0);
    slam.initial_scan(scan(x0, 1));
    slam.step(u, scan(Motion(mc).predict(x0, u), 2));
    return slam.last_report().ess;
  }
};

TEST(SiblingNormalizer, IdenticalChildrenAreWeighedAlike) {
  const ClutteredScene s;
  const int n = 8;
  const double sampled = s.step1_ess("sampled", n);
  const double pooled = s.step1_ess("sibling_mean", n);
  // every particle is a child of x_0 with the same map: the pooled Ĝ is the same for all, and so are the
  // proposal means (proposal_scale 0) unless the proposal's own sampler chose differently
  EXPECT_LT(sampled, 0.95 * n);  // the scene is ambiguous enough for the sampler's coverage to differ
  EXPECT_GT(pooled, sampled);
  EXPECT_NEAR(pooled, n, 1e-6 * n);
}

TEST(SiblingNormalizer, ConfigKeyIsValidated) {
  RbpfConfig c;
  c.particle_normalizer = "sibling_mean";
  EXPECT_NO_THROW(validate_rbpf_weighting(c));
  c.particle_normalizer = "siblings";
  EXPECT_THROW(validate_rbpf_weighting(c), ConfigError);
}

}  // namespace
}  // namespace glmbslam::backend
