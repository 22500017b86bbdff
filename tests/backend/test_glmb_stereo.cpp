// δ-GLMB joint prediction/update with the stereo models (issue 7): the Gibbs-sampled update against the
// brute-force enumeration of paper 000 Eq. 11–16 (glmb_brute_force.hpp) on a tiny 3D problem: a KITTI-like
// rectified stereo camera at a general SE(3) pose, z = (u_L, v, u_R), two tracks in view, one behind the
// camera (passive), two parent hypotheses, one birth candidate, two measurements (and the same with a third
// track in view); with and without the descriptor likelihood ratio.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "backend/glmb/glmb_update.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "core/lie.hpp"
#include "core/random.hpp"
#include "glmb_brute_force.hpp"
#include "stereo_test_support.hpp"

namespace glmbslam::backend {
namespace {

using test::flipped;
using test::kitti_calibration;
using test::random_descriptor;

using Model = StereoMeasurementModel;
using Map = GlmbMap<Model>;
using Updater = GlmbUpdater<Model>;
using Z = Updater::MeasurementSet;

/// Broad noise and a dense clutter model, so that every association has a findable weight.
StereoMeasurementConfig broad_sensor(bool use_descriptors) {
  StereoMeasurementConfig c;
  c.pixel_sigma = 6.0;
  c.min_depth = 1.0;
  c.max_depth = 20.0;
  c.p_detect_inside = 0.6;
  c.p_survive_inside = 0.7;
  c.p_survive_outside = 1.0;
  c.clutter_rate = 600.0;
  c.use_descriptors = use_descriptors;
  c.descriptor_threshold = 100.0;  // moderate log-ratios (|·| ≲ 2), so that no association becomes negligible
  c.descriptor_scale = 0.01;
  return c;
}

struct Problem {
  Pose3 x;
  Map prior;
  Z z;
};

/// Landmarks are placed in the camera frame of the pose x and moved to the world. Tracks 0, 1 (and with
/// `third_track` 3) are in view, track 2 is behind the camera; parent hypotheses {0, 1, 2 (, 3)} and
/// {0, 2 (, 3)}; one birth candidate; z_1 near track 0, z_2 near the birth.
Problem make_problem(const Model& model, RandomStream& rng, bool third_track) {
  Problem p;
  Vector6d xi;
  xi << 0.3, -0.1, 0.8, 0.02, -0.05, 0.03;  // (ρ, φ)
  p.x = se3_exp(xi);
  auto world = [&](double u, double v, double w) { return Eigen::Vector3d(p.x * Eigen::Vector3d(u, v, w)); };
  auto track = [&](int index, const Eigen::Vector3d& m, double var) {
    return Track<Model>{Label{0, index}, m, Eigen::Matrix3d::Identity() * var, random_descriptor(rng)};
  };
  p.prior.tracks.push_back(track(0, world(0.3, 0.1, 8.0), 0.05));
  p.prior.tracks.push_back(track(1, world(-0.2, 0.0, 9.0), 0.08));
  p.prior.tracks[1].cov(0, 2) = p.prior.tracks[1].cov(2, 0) = 0.02;  // a correlated one
  p.prior.tracks.push_back(track(2, world(0.4, 0.1, -5.0), 0.05));   // behind the camera: passive
  p.prior.hypotheses.push_back(Hypothesis{std::log(0.6), {0, 1, 2}});
  p.prior.hypotheses.push_back(Hypothesis{std::log(0.4), {0, 2}});
  if (third_track) {
    p.prior.tracks.push_back(track(3, world(0.5, 0.4, 8.5), 0.06));
    for (auto& h : p.prior.hypotheses) h.tracks.push_back(3);
  }
  BirthCandidate<Model> b;
  b.label = Label{1, 0};
  b.mean = world(0.0, 0.3, 7.5);
  b.cov = Eigen::Matrix3d::Identity() * 0.03;
  b.log_existence = std::log(0.4);
  b.appearance = random_descriptor(rng);
  p.prior.births.push_back(b);
  p.z.push_back(model.predict(p.x, world(0.32, 0.08, 7.9)) + Eigen::Vector3d(1.5, -2.0, 0.5));
  p.z.push_back(model.predict(p.x, world(0.02, 0.28, 7.6)) + Eigen::Vector3d(-1.0, 1.0, -2.5));
  for (std::size_t t = 0; t < p.prior.tracks.size(); ++t)
    EXPECT_EQ(model.in_field_of_view(p.x, p.prior.tracks[t].mean), t != 2) << "track " << t;
  EXPECT_TRUE(model.in_field_of_view(p.x, p.prior.births[0].mean));
  return p;
}

GlmbConfig enumeration_config() {
  GlmbConfig config;
  config.gate_threshold = 1e12;   // no gating, so brute force and sampler see the same table
  config.gibbs_samples = 200000;  // ≥ 20 expected visits of the least likely child (weight ≥ 1e-4)
  config.prune_threshold = 0.0;
  config.max_hypotheses = 100000;
  return config;
}

/// Runs the update on the problem and checks it against the enumeration (which must have `children`
/// distinct children); returns log Ĝ.
double check_against_enumeration(const Model& model, const Problem& p, std::size_t children) {
  const Updater updater(model, enumeration_config());
  RandomStream rng(11, 0);
  Map post;
  const GlmbUpdateStats stats = updater.update(p.prior, p.x, p.z, 1, rng, post);
  const auto brute = enumeration::merge_children(enumeration::brute_force(model, p.prior, p.x, p.z));
  EXPECT_EQ(brute.size(), children);
  EXPECT_EQ(stats.active_tracks, static_cast<int>(p.prior.tracks.size()) - 1);
  EXPECT_NO_FATAL_FAILURE(enumeration::expect_matches_enumeration(post, stats, brute, 1e-9, 1e-4));
  // the track behind the camera is copied unchanged into every hypothesis
  const auto& passive = p.prior.tracks[2];
  for (const auto& h : post.hypotheses) {
    int count = 0;
    for (auto t : h.tracks) {
      const auto& tr = post.tracks[t];
      if (tr.label != passive.label) continue;
      ++count;
      EXPECT_TRUE(tr.mean == passive.mean);
      EXPECT_TRUE(tr.cov == passive.cov);
      EXPECT_TRUE(tr.appearance == passive.appearance);
    }
    EXPECT_EQ(count, 1);
  }
  // next-step births, one per measurement, carrying its descriptor when the term is on
  EXPECT_EQ(post.births.size(), p.z.size());
  for (std::size_t j = 0; j < post.births.size(); ++j) {
    EXPECT_EQ(post.births[j].label, (Label{2, static_cast<int>(j)}));
    if (model.uses_appearance()) {
      EXPECT_TRUE(post.births[j].appearance == model.measurement_appearance(static_cast<int>(j)));
    }
  }
  return stats.log_normalizer;
}

// Children per parent with P rows and M = 2 measurements: 2^P (no detection) + 2P·2^(P−1) (one) +
// P(P−1)·2^(P−2) (both); the second parent's children (one row fewer) all equal first-parent children in
// which track 1 is dead, so they merge.
TEST(GlmbStereoUpdate, MatchesBruteForceEnumeration) {
  const Model model(kitti_calibration(), broad_sensor(false));
  RandomStream rng(5);
  const Problem two = make_problem(model, rng, false);  // 3 rows: 8 + 24 + 12
  check_against_enumeration(model, two, 44);
  const Problem three = make_problem(model, rng, true);  // 4 rows: 16 + 64 + 48
  check_against_enumeration(model, three, 128);
}

TEST(GlmbStereoUpdate, WithDescriptorsMatchesBruteForceEnumeration) {
  const Model geometric(kitti_calibration(), broad_sensor(false));
  const Model model(kitti_calibration(), broad_sensor(true));
  RandomStream rng(5);
  const Problem p = make_problem(model, rng, false);
  // z_1 carries a descriptor near track 0's, z_2 one near the birth's: log-ratios 0.01·(100 − d_H), from
  // +0.8 (20 bits) to about −0.3 against unrelated descriptors (~128 bits)
  model.set_measurement_appearance(
      {flipped(p.prior.tracks[0].appearance, 20), flipped(p.prior.births[0].appearance, 35)});
  ASSERT_NEAR(model.log_appearance_ratio(p.prior.tracks[0].appearance, 0), 0.8, 1e-12);
  ASSERT_NEAR(model.log_appearance_ratio(p.prior.births[0].appearance, 1), 0.65, 1e-12);
  const double log_g = check_against_enumeration(model, p, 44);
  // the term really changed the weights
  EXPECT_GT(std::abs(log_g - check_against_enumeration(geometric, p, 44)), 0.1);
}

// Innovation::update rejects a residual early when ν_i² > gate·S_ii (a bound of νᵀS⁻¹ν); it must decide every
// pair exactly as the full Mahalanobis test, also for strongly correlated S (landmark covariances elongated
// in depth) and residuals on the gate's boundary.
TEST(GlmbUpdateStereo, EarlyGateRejectionDecidesAsTheMahalanobisTest) {
  StereoMeasurementConfig c = broad_sensor(false);
  c.pixel_sigma = 0.7;
  const Model model(kitti_calibration(), c);
  RandomStream rng(5, 0);
  const Pose3 x = Pose3::Identity();
  const double gate = 16.0;
  int accepted = 0, rejected = 0, boundary = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Eigen::Vector3d mean(rng.uniform(-5.0, 5.0), rng.uniform(-2.0, 2.0), rng.uniform(4.0, 40.0));
    Eigen::Matrix3d A;
    for (int i = 0; i < 9; ++i) A.data()[i] = rng.normal();
    const Eigen::Vector3d axis = Eigen::Vector3d(rng.normal(), rng.normal(), 3.0).normalized();
    const Eigen::Matrix3d P = std::pow(10.0, rng.uniform(-4.0, 0.0)) * A * A.transpose() +
                              std::pow(10.0, rng.uniform(-2.0, 1.0)) * axis * axis.transpose();
    Innovation<Model> inn;
    inn.compute(model, x, mean, P);
    ASSERT_TRUE(inn.valid);
    const Eigen::Matrix3d S = inn.S_llt.reconstructedMatrix();
    const Eigen::LLT<Eigen::Matrix3d> L(S);
    for (int k = 0; k < 50; ++k) {
      // residuals along random directions, scaled to a Mahalanobis radius around the gate (some exactly on
      // it)
      const Eigen::Vector3d d(rng.normal(), rng.normal(), rng.normal());
      const double radius = k % 5 == 0 ? std::sqrt(gate) : std::sqrt(gate) * rng.uniform(0.2, 2.0);
      const Eigen::Vector3d nu = radius * Eigen::Vector3d(L.matrixL() * d.normalized());
      const Eigen::Vector3d z = inn.zhat + nu;
      const double d2 = inn.S_llt.matrixL().solve(model.residual(z, inn.zhat)).squaredNorm();
      Eigen::Vector3d m_out;
      double log_lik = 0.0;
      const bool in_gate = inn.update(model, mean, z, gate, &m_out, &log_lik);
      ASSERT_EQ(in_gate, d2 <= gate) << "d2 " << d2;
      if (in_gate) {
        EXPECT_DOUBLE_EQ(log_lik, inn.log_norm - 0.5 * d2);
        ++accepted;
      } else {
        ++rejected;
      }
      boundary += std::abs(d2 - gate) < 1e-9 * gate ? 1 : 0;
    }
  }
  EXPECT_GT(accepted, 2000);
  EXPECT_GT(rejected, 2000);
  EXPECT_GT(boundary, 100);  // pairs on the gate's boundary were compared too
}

}  // namespace
}  // namespace glmbslam::backend
