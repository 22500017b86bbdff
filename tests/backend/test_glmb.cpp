// δ-GLMB joint prediction/update: brute-force enumeration on a tiny problem, closed-form EKF update,
// map estimate, and degenerate inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "backend/glmb/glmb_update.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "glmb_brute_force.hpp"

namespace glmbslam::backend {
namespace {

using Model = RangeBearingModel;
using Map = GlmbMap<Model>;
using Updater = GlmbUpdater<Model>;
using Z = Updater::MeasurementSet;

RangeBearingConfig small_sensor() {
  RangeBearingConfig c;
  c.sigma_range = 0.1;
  c.sigma_bearing = 2.0 * M_PI / 180.0;
  c.max_range = 10.0;
  c.half_fov = M_PI / 2;
  c.p_detect_inside = 0.8;
  c.p_survive_inside = 0.9;
  c.clutter_rate = 2.0;
  return c;
}

Track<Model> make_track(int step, int index, double x, double y, double var) {
  return Track<Model>{Label{step, index}, Eigen::Vector2d(x, y), Eigen::Matrix2d::Identity() * var};
}

BirthCandidate<Model> make_birth(int step, int index, double x, double y, double var, double existence) {
  BirthCandidate<Model> b;
  b.label = Label{step, index};
  b.mean = Eigen::Vector2d(x, y);
  b.cov = Eigen::Matrix2d::Identity() * var;
  b.log_existence = std::log(existence);
  return b;
}

/// Update settings for comparisons with the enumeration: enough sweeps, nothing pruned or capped.
GlmbConfig enumeration_config(double gate_threshold) {
  GlmbConfig config;
  config.gate_threshold = gate_threshold;
  config.gibbs_samples = 20000;
  config.prune_threshold = 0.0;
  config.max_hypotheses = 100000;
  return config;
}

TEST(Innovation, EkfUpdateMatchesClosedForm) {
  const Model model(small_sensor());
  const Pose2 x(0, 0, 0);
  const Eigen::Vector2d mean(5.0, 0.0);
  const double p1 = 0.04, p2 = 0.09;
  const Eigen::Matrix2d P = Eigen::Vector2d(p1, p2).asDiagonal();
  Innovation<Model> inn;
  inn.compute(model, x, mean, P);
  const double sr2 = 0.01, sb2 = std::pow(2.0 * M_PI / 180.0, 2);
  const Eigen::Vector2d z(5.3, 0.02);
  Eigen::Vector2d m_out;
  double log_lik;
  ASSERT_TRUE(inn.update(model, mean, z, 1e9, &m_out, &log_lik));
  // H_m = diag(1, 1/5) at (5, 0): S = diag(p1 + σr², p2/25 + σb²), K = diag(p1/S1, (p2/5)/S2)
  const double S1 = p1 + sr2, S2 = p2 / 25.0 + sb2;
  EXPECT_NEAR(m_out(0), 5.0 + p1 / S1 * 0.3, 1e-12);
  EXPECT_NEAR(m_out(1), (p2 / 5.0) / S2 * 0.02, 1e-12);
  EXPECT_NEAR(inn.P_updated(0, 0), p1 * sr2 / S1, 1e-12);
  EXPECT_NEAR(inn.P_updated(1, 1), p2 * sb2 / S2, 1e-12);
  EXPECT_NEAR(inn.P_updated(0, 1), 0.0, 1e-12);
  const double expected =
      -std::log(2 * M_PI) - 0.5 * std::log(S1 * S2) - 0.5 * (0.3 * 0.3 / S1 + 0.02 * 0.02 / S2);
  EXPECT_NEAR(log_lik, expected, 1e-10);
}

TEST(GlmbUpdate, MatchesBruteForceEnumeration) {
  RangeBearingConfig sensor = small_sensor();  // broad noise, so that every association has a findable weight
  sensor.sigma_range = 1.0;
  sensor.sigma_bearing = 25.0 * M_PI / 180.0;
  sensor.clutter_rate = 1.0;
  sensor.p_detect_inside = 0.6;
  sensor.p_survive_inside = 0.7;
  const Model model(sensor);
  // no gating, so brute force and sampler see the same table
  const Updater updater(model, enumeration_config(1e12));
  Map prior;
  prior.tracks.push_back(make_track(0, 0, 4.0, 1.0, 0.05));   // in view
  prior.tracks.push_back(make_track(0, 1, 5.0, -1.5, 0.08));  // in view
  prior.tracks.push_back(make_track(0, 2, -6.0, 0.0, 0.05));  // behind the sensor: passive
  prior.hypotheses.push_back(Hypothesis{std::log(0.6), {0, 1, 2}});
  prior.hypotheses.push_back(Hypothesis{std::log(0.4), {0, 2}});
  prior.births.push_back(make_birth(1, 0, 3.0, 3.0, 0.02, 0.4));
  const Pose2 x(0.1, 0.0, 0.05);
  Z z;
  z.push_back(model.predict(x, Eigen::Vector2d(4.05, 0.95)));
  z.push_back(model.predict(x, Eigen::Vector2d(3.1, 2.9)));
  RandomStream rng(7, 0);
  Map post;
  const GlmbUpdateStats stats = updater.update(prior, x, z, 1, rng, post);
  // children of different parents with the same labelled densities merge
  const auto brute = enumeration::merge_children(enumeration::brute_force(model, prior, x, z));
  EXPECT_EQ(stats.active_tracks, 2);
  ASSERT_NO_FATAL_FAILURE(enumeration::expect_matches_enumeration(post, stats, brute, 1e-9));
  // without a gate every row reaches every measurement: the factorised normaliser also counts the
  // assignments that give one measurement to two rows, so it is a strict upper bound here
  EXPECT_GT(stats.log_normalizer_factorized, enumeration::log_normalizer(brute) + 1e-3);
  // next-step births: z_1 gates with a mapped landmark, but the gate is infinite here, so both are explained
  ASSERT_EQ(post.births.size(), 2u);
  EXPECT_EQ(post.births[0].label, (Label{2, 0}));
}

// When no measurement gates with two rows of a hypothesis, Σ_h w_h Π_rows Σ_entries η is the exact
// normaliser: the factorised one equals the enumeration; the sampler's sum misses its rarest children.
TEST(GlmbUpdate, FactorizedNormalizerIsExactWithoutSharedMeasurements) {
  RangeBearingConfig sensor = small_sensor();
  sensor.clutter_rate = 1.0;
  const Model model(sensor);
  // gate 1 − 1e-3 for 2 dof: the landmarks below are tens of σ apart
  const Updater updater(model, enumeration_config(13.8));
  Map prior;
  prior.tracks.push_back(make_track(0, 0, 4.0, 1.0, 0.01));
  prior.tracks.push_back(make_track(0, 1, 5.0, -1.5, 0.01));
  prior.tracks.push_back(make_track(0, 2, 2.0, 3.0, 0.01));
  prior.hypotheses.push_back(Hypothesis{std::log(0.7), {0, 1, 2}});
  prior.hypotheses.push_back(Hypothesis{std::log(0.3), {0, 2}});
  prior.births.push_back(make_birth(1, 0, 6.0, 3.0, 0.01, 0.3));
  const Pose2 x(0.0, 0.0, 0.0);
  Z z;
  z.push_back(model.predict(x, Eigen::Vector2d(4.02, 0.97)));
  z.push_back(model.predict(x, Eigen::Vector2d(5.05, -1.45)));
  z.push_back(model.predict(x, Eigen::Vector2d(6.03, 3.02)));
  z.push_back(model.predict(x, Eigen::Vector2d(-3.0, 8.0)));  // clutter: gates with nothing
  RandomStream rng(5, 0);
  Map post;
  const GlmbUpdateStats stats = updater.update(prior, x, z, 1, rng, post);
  const auto brute = enumeration::merge_children(enumeration::brute_force(model, prior, x, z));
  const double exact = enumeration::log_normalizer(brute);
  // the ungated enumeration's extra associations are tens of σ off (weight ~e^{-100}): the same to 1e-9
  EXPECT_NEAR(stats.log_normalizer_factorized, exact, 1e-9);
  // the sampled normaliser sums the children the sampler found: a lower bound, short by the missed ones
  EXPECT_LE(stats.log_normalizer, exact + 1e-12);
  EXPECT_GT(stats.log_normalizer, exact - 1e-2);
}

TEST(GlmbUpdate, EstimateUsesMapCardinality) {
  Map m;
  m.tracks.push_back(make_track(0, 0, 1, 1, 0.1));
  m.tracks.push_back(make_track(0, 1, 2, 2, 0.1));
  m.tracks.push_back(make_track(0, 2, 3, 3, 0.1));
  m.hypotheses.push_back(Hypothesis{std::log(0.4), {0, 1, 2}});
  m.hypotheses.push_back(Hypothesis{std::log(0.35), {0, 1}});
  m.hypotheses.push_back(Hypothesis{std::log(0.25), {0, 2}});
  const auto est = estimate_map(m);  // ρ(2) = 0.6 > ρ(3) = 0.4 → best 2-hypothesis {0, 1}
  ASSERT_EQ(est.size(), 2u);
  EXPECT_EQ(est[0].label, (Label{0, 0}));
  EXPECT_EQ(est[1].label, (Label{0, 1}));
  EXPECT_NEAR(est[0].existence, 1.0, 1e-12);
  EXPECT_NEAR(est[1].existence, 0.75, 1e-12);
}

class GlmbDegenerate : public ::testing::Test {
 protected:
  GlmbDegenerate() : model_(small_sensor()), updater_(model_, GlmbConfig{}) {
    prior_.tracks.push_back(make_track(0, 0, 4.0, 0.0, 0.05));
    prior_.hypotheses.push_back(Hypothesis{0.0, {0}});
  }
  Model model_;
  Updater updater_;
  Map prior_;
  RandomStream rng_{3, 0};
};

TEST_F(GlmbDegenerate, EmptyMeasurementSet) {
  Map post;
  const auto stats = updater_.update(prior_, Pose2(0, 0, 0), Z{}, 1, rng_, post);
  // children: dead (1 − p_S) and missed (p_S (1 − p_D)); Ĝ = 0.1 + 0.9·0.2
  EXPECT_NEAR(stats.log_normalizer, std::log(0.1 + 0.9 * 0.2), 1e-12);
  ASSERT_EQ(post.hypotheses.size(), 2u);
  EXPECT_NEAR(std::exp(post.hypotheses[0].log_weight), 0.18 / 0.28, 1e-12);
  EXPECT_TRUE(post.births.empty());
}

TEST_F(GlmbDegenerate, AllClutter) {
  Map post;
  Z z;
  z.push_back(Eigen::Vector2d(8.0, 1.0));
  z.push_back(Eigen::Vector2d(2.0, -1.2));
  const auto stats = updater_.update(prior_, Pose2(0, 0, 0), z, 1, rng_, post);
  EXPECT_NEAR(stats.log_normalizer, std::log(0.1 + 0.9 * 0.2), 1e-12);  // nothing gates
  ASSERT_EQ(post.births.size(), 2u);
  EXPECT_NEAR(std::exp(post.births[0].log_existence), 1e-4, 1e-15);  // unexplained
  for (const auto& b : post.births) EXPECT_TRUE(b.mean.allFinite());
}

TEST_F(GlmbDegenerate, LandmarkExactlyAtTheSensor) {
  Map post;
  Z z;
  z.push_back(Eigen::Vector2d(0.0, 0.0));
  const auto stats = updater_.update(prior_, Pose2(4.0, 0.0, 0.0), z, 1, rng_, post);
  EXPECT_EQ(stats.active_tracks, 0);  // out of view: copied through
  ASSERT_EQ(post.hypotheses.size(), 1u);
  ASSERT_EQ(post.tracks.size(), 1u);
  EXPECT_TRUE(post.tracks[0].mean.allFinite());
  EXPECT_NEAR(stats.log_normalizer, 0.0, 1e-12);
  ASSERT_EQ(post.births.size(), 1u);
  EXPECT_TRUE(post.births[0].mean.allFinite() && post.births[0].cov.allFinite());
}

TEST_F(GlmbDegenerate, NanMeasurementIsRejected) {
  Map post;
  Z z;
  z.push_back(Eigen::Vector2d(1.0, std::nan("")));
  EXPECT_THROW(updater_.update(prior_, Pose2(0, 0, 0), z, 1, rng_, post), InputError);
}

}  // namespace
}  // namespace glmbslam::backend
