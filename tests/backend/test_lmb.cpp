// LMB-SLAM: the LMB approximation keeps each label's existence and spatial density of the δ-GLMB it comes
// from — checked against brute-force enumeration of every association map of a tiny joint
// prediction/update, and against the δ-GLMB update of the same prior followed by lmb_from_glmb — plus
// component reduction by moment matching and an end-to-end filter run.
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "backend/glmb/glmb_update.hpp"
#include "backend/lmb/lmb_map.hpp"
#include "backend/lmb/lmb_slam.hpp"
#include "backend/lmb/lmb_update.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace glmbslam::backend {
namespace {

using Model = RangeBearingModel;
using Comp = LmbComponent<Model>;
using CompList = std::vector<Comp, Eigen::aligned_allocator<Comp>>;
using Z = LmbUpdater<Model>::MeasurementSet;

RangeBearingConfig tiny_sensor() {
  RangeBearingConfig c;
  c.sigma_range = 0.5;
  c.sigma_bearing = 3.0 * M_PI / 180.0;
  c.max_range = 20.0;
  c.half_fov = M_PI;
  c.p_detect_inside = 0.8;
  c.p_survive_inside = 1.0;
  c.clutter_rate = 100.0;  // κ of the order of the likelihoods: every association map has a real weight
  return c;
}

/// Mean and covariance of a label's density given as weighted components.
struct Moments {
  double mass = 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();  ///< Σ w (P + m mᵀ)
  void add(double w, const Eigen::Vector2d& m, const Eigen::Matrix2d& P) {
    mass += w;
    mean += w * m;
    second += w * (P + m * m.transpose());
  }
  Eigen::Vector2d mu() const { return mean / mass; }
  Eigen::Matrix2d cov() const { return second / mass - mu() * mu().transpose(); }
};

Moments moments_of(const LmbMap<Model>& map, std::size_t t) {
  Moments m;
  const auto& tr = map.tracks[t];
  for (int c = tr.first; c < tr.first + tr.count; ++c)
    m.add(map.components[c].weight, map.components[c].mean, map.components[c].cov);
  return m;
}

int find_label(const LmbMap<Model>& map, const Label& l) {
  for (std::size_t t = 0; t < map.tracks.size(); ++t)
    if (map.tracks[t].label == l) return static_cast<int>(t);
  return -1;
}

/// The tiny problem: label A (r = 0.9, one Gaussian), label B (r = 0.6, two Gaussians) and a birth C
/// (r_B = 0.3), two measurements that each of them could explain.
struct TinyProblem {
  Model model{tiny_sensor()};
  Pose2 x{0.0, 0.0, 0.1};
  LmbMap<Model> prior;
  Z z;
  TinyProblem() {
    const Eigen::Matrix2d P = Eigen::Matrix2d::Identity() * 0.3;
    prior.add_track(Label{1, 0}, 0.9, CompList{Comp{1.0, {5.0, 1.0}, P}});
    prior.add_track(Label{1, 1}, 0.6, CompList{Comp{0.7, {5.5, 2.0}, P}, Comp{0.3, {6.0, 1.5}, 0.5 * P}});
    BirthCandidate<Model> bc;
    bc.label = Label{2, 0};
    bc.mean = Eigen::Vector2d(5.2, 1.8);
    bc.cov = Eigen::Matrix2d::Identity() * 0.5;
    bc.log_existence = std::log(0.3);
    prior.births.push_back(bc);
    z.push_back(model.predict(x, Eigen::Vector2d(5.1, 1.2)));
    z.push_back(model.predict(x, Eigen::Vector2d(5.6, 1.8)));
  }
};

/// EKF update of one Gaussian, written out: likelihood N(z; h(m), H P Hᵀ + R), updated mean and covariance.
double ekf(const Model& model, const Pose2& x, const Eigen::Vector2d& m, const Eigen::Matrix2d& P,
           const Eigen::Vector2d& z, Eigen::Vector2d* m_out, Eigen::Matrix2d* P_out) {
  Model::LandmarkJacobian H;
  const Eigen::Vector2d zhat = model.linearize(x, m, nullptr, &H);
  const Eigen::Matrix2d S = H * P * H.transpose() + model.noise();
  const Eigen::Vector2d nu = model.residual(z, zhat);
  const Eigen::Matrix<double, 2, 2> K = P * H.transpose() * S.inverse();
  *m_out = m + K * nu;
  *P_out = (Eigen::Matrix2d::Identity() - K * H) * P;
  return std::exp(-0.5 * nu.dot(S.inverse() * nu)) / (2.0 * M_PI * std::sqrt(S.determinant()));
}

TEST(LmbUpdate, ExistenceAndDensityMatchEnumerationOfEveryAssociationMap) {
  const TinyProblem tp;
  GlmbConfig gc;
  gc.gate_threshold = 1e9;
  gc.gibbs_samples = 20000;
  gc.births = false;
  LmbConfig lc;
  lc.existence_threshold = 0.0;
  lc.max_components = 100;
  lc.component_prune = 0.0;
  const LmbUpdater<Model> updater(tp.model, gc, lc);
  RandomStream rng(5, 0);
  LmbMap<Model> post;
  const LmbUpdateStats stats = updater.update(tp.prior, tp.x, tp.z, 1, rng, post);

  // brute force: rows A, B, C; γ ∈ {−1 dead, 0 missed, 1, 2}, detections distinct
  const double pd = 0.8, kappa = std::exp(tp.model.log_clutter_intensity(tp.z[0]));
  struct Row {
    Label label;
    double r;
    CompList comps;
  };
  std::vector<Row> rows;
  for (std::size_t t = 0; t < 2; ++t) {
    const auto& tr = tp.prior.tracks[t];
    rows.push_back(Row{
        tr.label, tr.existence,
        CompList(tp.prior.components.begin() + tr.first, tp.prior.components.begin() + tr.first + tr.count)});
  }
  rows.push_back(Row{tp.prior.births[0].label, 0.3,
                     CompList{Comp{1.0, tp.prior.births[0].mean, tp.prior.births[0].cov}}});
  // per row and choice: η and the density's moments
  std::vector<std::vector<double>> eta(3, std::vector<double>(4, 0.0));
  std::vector<std::vector<Moments>> dens(3, std::vector<Moments>(4));
  for (int i = 0; i < 3; ++i) {
    const Row& r = rows[i];
    eta[i][0] = 1.0 - r.r;
    eta[i][1] = r.r * (1.0 - pd);
    for (const auto& c : r.comps) dens[i][1].add(c.weight, c.mean, c.cov);
    for (int j = 0; j < 2; ++j) {
      double q = 0.0;
      for (const auto& c : r.comps) {
        Eigen::Vector2d m;
        Eigen::Matrix2d P;
        const double g = ekf(tp.model, tp.x, c.mean, c.cov, tp.z[j], &m, &P);
        q += c.weight * g;
        dens[i][2 + j].add(c.weight * g, m, P);
      }
      eta[i][2 + j] = r.r * pd * q / kappa;
    }
  }
  double total = 0.0;
  std::vector<double> exist(3, 0.0);
  std::vector<Moments> mom(3);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 4; ++c) {
        const int g[3] = {a, b, c};
        bool ok = true;
        for (int i = 0; i < 3; ++i)
          for (int k = i + 1; k < 3; ++k) ok &= !(g[i] >= 2 && g[i] == g[k]);
        if (!ok) continue;
        const double w = eta[0][a] * eta[1][b] * eta[2][c];
        total += w;
        for (int i = 0; i < 3; ++i) {
          if (g[i] == 0) continue;
          exist[i] += w;
          const Moments& d = dens[i][g[i]];
          mom[i].add(w, d.mu(), d.cov());
        }
      }
  EXPECT_NEAR(stats.log_normalizer, std::log(total), 1e-9);
  ASSERT_EQ(post.tracks.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const int t = find_label(post, rows[i].label);
    ASSERT_GE(t, 0) << i;
    EXPECT_NEAR(post.tracks[t].existence, exist[i] / total, 1e-9) << "label " << i;
    const Moments m = moments_of(post, static_cast<std::size_t>(t));
    EXPECT_NEAR((m.mu() - mom[i].mu()).norm(), 0.0, 1e-9) << "label " << i;
    EXPECT_NEAR((m.cov() - mom[i].cov()).norm(), 0.0, 1e-9) << "label " << i;
  }
  // moment matching to one component per label keeps the same existence, mean and covariance
  lc.max_components = 1;
  const LmbUpdater<Model> merged_updater(tp.model, gc, lc);
  RandomStream rng2(5, 0);
  LmbMap<Model> merged;
  merged_updater.update(tp.prior, tp.x, tp.z, 1, rng2, merged);
  for (int i = 0; i < 3; ++i) {
    const int t = find_label(merged, rows[i].label);
    ASSERT_GE(t, 0);
    EXPECT_EQ(merged.tracks[t].count, 1);
    EXPECT_NEAR(merged.tracks[t].existence, exist[i] / total, 1e-9);
    const Comp& c = merged.components[merged.tracks[t].first];
    EXPECT_NEAR((c.mean - mom[i].mu()).norm(), 0.0, 1e-9);
    EXPECT_NEAR((c.cov - mom[i].cov()).norm(), 0.0, 1e-9);
  }
}

TEST(LmbUpdate, EqualsTheLmbApproximationOfTheDeltaGlmbUpdate) {
  // the same prior as a δ-GLMB: hypotheses ∅, {A}, {B₁}, {B₂}, {A, B₁}, {A, B₂} (B's two components as two
  // tracks of one label), the birth as a birth candidate
  const TinyProblem tp;
  GlmbMap<Model> glmb;
  const auto& pc = tp.prior.components;
  glmb.tracks.push_back(Track<Model>{Label{1, 0}, pc[0].mean, pc[0].cov, {}});
  glmb.tracks.push_back(Track<Model>{Label{1, 1}, pc[1].mean, pc[1].cov, {}});
  glmb.tracks.push_back(Track<Model>{Label{1, 1}, pc[2].mean, pc[2].cov, {}});
  const double rA = 0.9, rB = 0.6, wB[2] = {0.7, 0.3};
  auto hyp = [&](double w, std::vector<std::uint32_t> t) {
    glmb.hypotheses.push_back(Hypothesis{std::log(w), t});
  };
  hyp((1 - rA) * (1 - rB), {});
  hyp(rA * (1 - rB), {0});
  hyp((1 - rA) * rB * wB[0], {1});
  hyp((1 - rA) * rB * wB[1], {2});
  hyp(rA * rB * wB[0], {0, 1});
  hyp(rA * rB * wB[1], {0, 2});
  glmb.births = tp.prior.births;
  GlmbConfig gc;
  gc.gate_threshold = 1e9;
  gc.gibbs_samples = 20000;
  gc.births = false;
  gc.max_hypotheses = 100000;
  gc.prune_threshold = 0.0;
  const GlmbUpdater<Model> glmb_updater(tp.model, gc);
  RandomStream rng(9, 0);
  GlmbMap<Model> glmb_post;
  glmb_updater.update(glmb, tp.x, tp.z, 1, rng, glmb_post);
  const LmbMap<Model> approx = lmb_from_glmb(glmb_post);

  LmbConfig lc;
  lc.existence_threshold = 0.0;
  lc.max_components = 100;
  lc.component_prune = 0.0;
  const LmbUpdater<Model> updater(tp.model, gc, lc);
  RandomStream rng2(5, 0);
  LmbMap<Model> post;
  updater.update(tp.prior, tp.x, tp.z, 1, rng2, post);
  ASSERT_EQ(approx.tracks.size(), post.tracks.size());
  for (std::size_t t = 0; t < post.tracks.size(); ++t) {
    const int s = find_label(approx, post.tracks[t].label);
    ASSERT_GE(s, 0);
    EXPECT_NEAR(approx.tracks[s].existence, post.tracks[t].existence, 1e-9);
    const Moments a = moments_of(approx, static_cast<std::size_t>(s)), b = moments_of(post, t);
    EXPECT_NEAR((a.mu() - b.mu()).norm(), 0.0, 1e-9);
    EXPECT_NEAR((a.cov() - b.cov()).norm(), 0.0, 1e-9);
  }
}

TEST(LmbMap, ApproximationOfAGlmbSumsTheHypothesesOfEachLabel) {
  GlmbMap<Model> g;
  const Eigen::Matrix2d P = Eigen::Matrix2d::Identity();
  g.tracks.push_back(Track<Model>{Label{1, 0}, {0.0, 0.0}, P, {}});
  g.tracks.push_back(Track<Model>{Label{1, 0}, {1.0, 0.0}, 2.0 * P, {}});
  g.tracks.push_back(Track<Model>{Label{2, 3}, {5.0, 5.0}, P, {}});
  g.hypotheses.push_back(Hypothesis{std::log(0.5), {0, 2}});
  g.hypotheses.push_back(Hypothesis{std::log(0.3), {1}});
  g.hypotheses.push_back(Hypothesis{std::log(0.2), {}});
  const LmbMap<Model> l = lmb_from_glmb(g);
  ASSERT_EQ(l.tracks.size(), 2u);
  EXPECT_NEAR(l.tracks[0].existence, 0.8, 1e-12);
  EXPECT_NEAR(l.tracks[1].existence, 0.5, 1e-12);
  ASSERT_EQ(l.tracks[0].count, 2);
  EXPECT_NEAR(l.components[0].weight, 0.5 / 0.8, 1e-12);
  EXPECT_NEAR(l.components[1].weight, 0.3 / 0.8, 1e-12);
  // moment match of label (1, 0): mean 0.375, variance 1·0.625 + 2·0.375 + spread
  CompList comps(l.components.begin(), l.components.begin() + 2);
  reduce_components<Model>(comps, 0.0, 1);
  ASSERT_EQ(comps.size(), 1u);
  EXPECT_NEAR(comps[0].mean.x(), 0.375, 1e-12);
  EXPECT_NEAR(comps[0].cov(0, 0), 0.625 + 2.0 * 0.375 + 0.625 * 0.375 * 0.375 + 0.375 * 0.625 * 0.625, 1e-12);
  EXPECT_NEAR(comps[0].cov(1, 1), 0.625 + 2.0 * 0.375, 1e-12);
}

TEST(LmbSlam, TracksASmallSceneWithBothProposals) {
  UnicycleMotionConfig mc;
  mc.dt = 1.0;
  mc.sigma_v = 0.1;
  mc.sigma_omega = 0.5 * M_PI / 180.0;
  RangeBearingConfig sc;
  sc.max_range = 30.0;
  sc.half_fov = M_PI;
  sc.sigma_range = 0.1;
  sc.sigma_bearing = 0.5 * M_PI / 180.0;
  sc.p_detect_inside = 0.95;
  sc.p_survive_inside = 1.0;
  sc.clutter_rate = 1.0;
  const UnicycleMotion motion(mc);
  const Model model(sc);
  const std::vector<Eigen::Vector2d> landmarks = {{5, 5}, {10, -4}, {15, 6}, {20, -5}, {25, 3}, {8, 12}};
  for (const char* proposal : {"optimal", "prior"}) {
    RbpfConfig rc;
    rc.particles = 5;
    rc.seed = 4;
    rc.proposal = proposal;
    rc.glmb.birth_prob_unexplained = 0.05;
    rc.glmb.birth_prob_explained = 0.01;
    LmbSlam<UnicycleMotion, Model> slam(motion, model, rc, LmbConfig(), Pose2(0, 0, 0));
    RandomStream rng(11, 0);
    Pose2 x(0, 0, 0);
    auto scan = [&](bool clutter) {
      LmbSlam<UnicycleMotion, Model>::MeasurementSet Z;
      for (const auto& m : landmarks) {
        if (rng.uniform() > sc.p_detect_inside) continue;
        Eigen::Vector2d z = model.predict(x, m);
        z(0) += sc.sigma_range * rng.normal();
        z(1) += sc.sigma_bearing * rng.normal();
        Z.push_back(z);
      }
      if (clutter && rng.uniform() < 0.6)
        Z.push_back(Eigen::Vector2d(rng.uniform(1.0, 30.0), rng.uniform(-M_PI, M_PI)));
      return Z;
    };
    slam.initial_scan(scan(true));
    // clutter in every scan but the last three: a clutter point seen last is a likely new landmark until
    // scans in view miss it, so the final map holds exactly the six trees
    for (int k = 1; k <= 25; ++k) {
      const Eigen::Vector2d u(1.0, 0.0);
      x = motion.predict(x, u);
      slam.step(u, scan(k <= 22));
    }
    EXPECT_LT((slam.pose().head<2>() - x.head<2>()).norm(), 0.5) << proposal;
    const auto est = slam.landmarks();
    EXPECT_EQ(est.size(), landmarks.size()) << proposal;
    for (const auto& m : landmarks) {
      double best = 1e9;
      for (const auto& e : est) best = std::min(best, (e.mean - m).norm());
      EXPECT_LT(best, 0.5) << proposal;
    }
  }
}

// A frame whose sensor saw nothing (blind_step): the maps stay as they were and the pose is the motion
// model's prediction.
TEST(LmbSlam, ABlindStepMovesThePoseAndLeavesTheMap) {
  UnicycleMotionConfig mc;
  mc.dt = 1.0;
  RangeBearingConfig sc;
  sc.max_range = 30.0;
  sc.half_fov = M_PI;
  sc.clutter_rate = 1.0;
  const UnicycleMotion motion(mc);
  const Model model(sc);
  RbpfConfig rc;
  rc.particles = 1;
  rc.single_particle = "mean";
  LmbSlam<UnicycleMotion, Model> slam(motion, model, rc, LmbConfig(), Pose2(0, 0, 0));
  Pose2 x(0, 0, 0);
  const std::vector<Eigen::Vector2d> landmarks = {{5, 5}, {10, -4}, {15, 6}};
  auto scan = [&] {
    LmbSlam<UnicycleMotion, Model>::MeasurementSet Z;
    for (const auto& m : landmarks) Z.push_back(model.predict(x, m));
    return Z;
  };
  slam.initial_scan(scan());
  const Eigen::Vector2d u(1.0, 0.0);
  for (int k = 1; k <= 5; ++k) {
    x = motion.predict(x, u);
    slam.step(u, scan());
  }
  const auto before = slam.landmarks();
  ASSERT_EQ(before.size(), landmarks.size());
  const auto* map = slam.particles()[0].map.get();
  const Pose2 pose = slam.pose();
  slam.blind_step(u);
  EXPECT_EQ(slam.particles()[0].map.get(), map);
  EXPECT_EQ(slam.pose(), motion.predict(pose, u));
  const auto after = slam.landmarks();
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t j = 0; j < after.size(); ++j) {
    EXPECT_EQ(after[j].existence, before[j].existence);
    EXPECT_EQ(after[j].mean, before[j].mean);
  }
}

TEST(LmbSlam, SameSeedSameOutputForAnyThreadCount) {
  RangeBearingConfig sc;
  sc.max_range = 30.0;
  sc.half_fov = M_PI;
  const Model model(sc);
  UnicycleMotionConfig mc;
  const UnicycleMotion motion(mc);
  auto run = [&](int threads) {
    set_thread_count(threads);
    RbpfConfig rc;
    rc.particles = 6;
    rc.seed = 2;
    LmbSlam<UnicycleMotion, Model> slam(motion, model, rc, LmbConfig(), Pose2(0, 0, 0));
    LmbSlam<UnicycleMotion, Model>::MeasurementSet Z;
    for (int k = 1; k <= 10; ++k) {
      Z.clear();
      Z.push_back(model.predict(Pose2(k, 0, 0), Eigen::Vector2d(10, 4)));
      Z.push_back(model.predict(Pose2(k, 0, 0), Eigen::Vector2d(14, -3)));
      slam.step(Eigen::Vector2d(1.0, 0.0), Z);
    }
    return slam.trajectory();
  };
  const auto a = run(1), b = run(2);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]);
}

TEST(LmbSlam, ConfigIsValidated) {
  RbpfConfig rc;
  rc.proposal = "mh";
  EXPECT_THROW((LmbSlam<UnicycleMotion, Model>(UnicycleMotion(UnicycleMotionConfig()), Model(), rc,
                                               LmbConfig(), Pose2(0, 0, 0))),
               ConfigError);
  LmbConfig lc;
  lc.max_components = 0;
  EXPECT_THROW((LmbSlam<UnicycleMotion, Model>(UnicycleMotion(UnicycleMotionConfig()), Model(), RbpfConfig(),
                                               lc, Pose2(0, 0, 0))),
               ConfigError);
  RbpfConfig weighting;
  weighting.weighting = "exact";  // the checks shared with δ-GLMB-SLAM (labelled_map_filter.hpp)
  EXPECT_THROW((LmbSlam<UnicycleMotion, Model>(UnicycleMotion(UnicycleMotionConfig()), Model(), weighting,
                                               LmbConfig(), Pose2(0, 0, 0))),
               ConfigError);
}

TEST(LmbSlam, RejectsNonFiniteInputWithoutChangingStateAndScansOnlyFirst) {
  const Model model;
  LmbSlam<UnicycleMotion, Model> slam(UnicycleMotion(UnicycleMotionConfig()), model, RbpfConfig(),
                                      LmbConfig(), Pose2(0, 0, 0));
  LmbSlam<UnicycleMotion, Model>::MeasurementSet z{model.predict(Pose2(0, 0, 0), Eigen::Vector2d(10, 4))};
  slam.initial_scan(z);
  z.emplace_back(std::nan(""), 0.0);
  EXPECT_THROW(slam.step(Eigen::Vector2d(1.0, 0.0), z), InputError);
  z.pop_back();
  EXPECT_THROW(slam.step(Eigen::Vector2d(std::nan(""), 0.0), z), InputError);
  EXPECT_EQ(slam.steps(), 0);
  slam.step(Eigen::Vector2d(1.0, 0.0), z);
  EXPECT_EQ(slam.steps(), 1);
  EXPECT_THROW(slam.initial_scan(z), std::logic_error);
}

}  // namespace
}  // namespace glmbslam::backend
