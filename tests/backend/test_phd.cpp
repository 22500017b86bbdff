// RB-PHD-SLAM 1.0: GM-PHD update against closed forms and numerical integration, pruning/merging, filter
// determinism across thread counts.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/phd/gm_phd_map.hpp"
#include "backend/phd/phd_slam.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace glmbslam::backend {
namespace {

using Model = RangeBearingModel;
using Map = GmPhdMap<Model>;
using Updater = GmPhdUpdater<Model>;
using Z = Updater::MeasurementSet;

RangeBearingConfig sensor() {
  RangeBearingConfig c;
  c.sigma_range = 0.2;
  c.sigma_bearing = 1.0 * M_PI / 180.0;
  c.max_range = 20.0;
  c.half_fov = M_PI;
  c.p_detect_inside = 0.8;
  c.clutter_rate = 2.0;
  return c;
}

Map one_component(const Eigen::Vector2d& mean, double sigma, double weight) {
  Map m;
  m.components.push_back({mean, Eigen::Matrix2d::Identity() * sigma * sigma, weight});
  return m;
}

TEST(GmPhd, UpdateMatchesTheGmPhdFormulas) {
  const Model model(sensor());
  PhdConfig cfg;
  cfg.merge_threshold = 0.0;  // keep components apart
  const Updater up(model, cfg);
  const Pose2 x(0.0, 0.0, 0.3);
  const Map prior = one_component({5.0, 2.0}, 0.3, 0.7);
  Z z;
  z.push_back(model.predict(x, Eigen::Vector2d(5.1, 1.9)));
  Map post;
  const auto stats = up.update(prior, x, z, post);
  // closed form
  Model::LandmarkJacobian H;
  const Eigen::Vector2d zhat = model.linearize(x, prior.components[0].mean, nullptr, &H);
  const Eigen::Matrix2d S = H * prior.components[0].cov * H.transpose() + model.noise();
  const Eigen::Vector2d nu = model.residual(z[0], zhat);
  const double q = std::exp(-0.5 * nu.dot(S.inverse() * nu)) / (2.0 * M_PI * std::sqrt(S.determinant()));
  const double kappa = std::exp(model.log_clutter_intensity(z[0]));
  const double pd = 0.8, w = 0.7;
  const double w_det = pd * w * q / (kappa + pd * w * q);
  ASSERT_EQ(post.components.size(), 2u);  // missed + detected, no birth (the measurement is explained)
  if (post.components[0].mean != prior.components[0].mean) std::swap(post.components[0], post.components[1]);
  EXPECT_EQ(post.components[0].mean, prior.components[0].mean);  // the missed component
  EXPECT_NEAR(post.components[0].weight, (1 - pd) * w, 1e-12);
  EXPECT_NEAR(post.components[1].weight, w_det, 1e-12);
  const Eigen::Matrix<double, 2, 2> K = prior.components[0].cov * H.transpose() * S.inverse();
  EXPECT_NEAR((post.components[1].mean - (prior.components[0].mean + K * nu)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(
      (post.components[1].cov - (Eigen::Matrix2d::Identity() - K * H) * prior.components[0].cov).norm(), 0.0,
      1e-12);
  // empty-map likelihood (002 Eq. 15)
  EXPECT_NEAR(stats.log_likelihood, std::log(kappa) + ((1 - pd) * w + w_det) - w - model.clutter_rate(),
              1e-12);
  EXPECT_EQ(stats.births, 0);
}

TEST(GmPhd, PoissonLikelihoodEqualsNumericalIntegration) {
  // For a Poisson map prior with intensity v and Poisson clutter, g(Z) = e^{−λ − ∫p_D v} Π_z (κ(z) + ∫p_D
  // g(z|m) v(m) dm) exactly; the EKF evaluates ∫p_D g v in closed form, which must match a grid integral for
  // a small covariance.
  const Model model(sensor());
  PhdConfig cfg;
  cfg.likelihood = "poisson";
  const Updater up(model, cfg);
  const Pose2 x(1.0, -1.0, 0.5);
  const Eigen::Vector2d mu(6.0, 3.0);
  const double sigma = 0.1, w = 0.9;
  const Map prior = one_component(mu, sigma, w);
  Z z;
  z.push_back(model.predict(x, Eigen::Vector2d(6.05, 2.95)));
  z.push_back(Eigen::Vector2d(10.0, -1.0));  // clutter
  Map post;
  const double log_g = up.update(prior, x, z, post).log_likelihood;
  const double pd = 0.8;
  const Eigen::Matrix2d R = model.noise();
  double expected = -model.clutter_rate() - pd * w;
  for (const auto& zj : z) {
    double integral = 0.0;
    const double h = sigma / 25.0;
    for (double dx = -6 * sigma; dx <= 6 * sigma; dx += h) {
      for (double dy = -6 * sigma; dy <= 6 * sigma; dy += h) {
        const Eigen::Vector2d m = mu + Eigen::Vector2d(dx, dy);
        const Eigen::Vector2d nu = model.residual(zj, model.predict(x, m));
        const double g = std::exp(-0.5 * nu.dot(R.inverse() * nu)) / (2 * M_PI * std::sqrt(R.determinant()));
        const double v =
            w * std::exp(-0.5 * (dx * dx + dy * dy) / (sigma * sigma)) / (2 * M_PI * sigma * sigma);
        integral += pd * g * v * h * h;
      }
    }
    expected += std::log(std::exp(model.log_clutter_intensity(zj)) + integral);
  }
  EXPECT_NEAR(log_g, expected, 2e-3);
}

TEST(GmPhd, PassiveComponentsAreCopiedAndBirthsComeFromUnexplainedMeasurements) {
  const Model model(sensor());
  const Updater up(model, PhdConfig{});
  Map prior = one_component({100.0, 0.0}, 0.5, 0.9);  // out of range: passive
  const Pose2 x(0.0, 0.0, 0.0);
  Z z;
  z.push_back(Eigen::Vector2d(3.0, 0.2));
  Map post;
  const auto stats = up.update(prior, x, z, post);
  ASSERT_EQ(post.components.size(), 2u);
  EXPECT_EQ(post.components[0].weight, 0.9);
  EXPECT_EQ(post.components[0].mean, prior.components[0].mean);
  EXPECT_EQ(stats.births, 1);
  EXPECT_NEAR((post.components[1].mean - Eigen::Vector2d(3.0 * std::cos(0.2), 3.0 * std::sin(0.2))).norm(), 0,
              1e-12);
  EXPECT_EQ(post.components[1].weight, PhdConfig{}.birth_weight);
  EXPECT_NEAR(stats.log_likelihood, model.log_clutter_intensity(z[0]) - model.clutter_rate(), 1e-12);
}

TEST(GmPhd, PruningAndMergingFollowVoAndMa) {
  RangeBearingConfig c = sensor();
  c.p_detect_inside = 0.5;
  const Model model(c);
  PhdConfig cfg;
  cfg.merge_threshold = 50.0;
  cfg.prune_threshold = 0.05;
  const Updater up(model, cfg);
  Map prior;
  prior.components.push_back({Eigen::Vector2d(5.0, 0.0), Eigen::Matrix2d::Identity() * 0.04, 0.6});
  prior.components.push_back({Eigen::Vector2d(5.3, 0.1), Eigen::Matrix2d::Identity() * 0.09, 0.4});
  prior.components.push_back(
      {Eigen::Vector2d(9.0, 5.0), Eigen::Matrix2d::Identity() * 0.04, 0.08});  // pruned
  Map post;
  up.update(prior, Pose2(0, 0, 0), Z{}, post);
  ASSERT_EQ(post.components.size(), 1u);
  const double w = 0.5 * (0.6 + 0.4);
  const Eigen::Vector2d mean = (0.3 * Eigen::Vector2d(5.0, 0.0) + 0.2 * Eigen::Vector2d(5.3, 0.1)) / w;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  cov += 0.3 * (Eigen::Matrix2d::Identity() * 0.04 +
                (Eigen::Vector2d(5.0, 0.0) - mean) * (Eigen::Vector2d(5.0, 0.0) - mean).transpose());
  cov += 0.2 * (Eigen::Matrix2d::Identity() * 0.09 +
                (Eigen::Vector2d(5.3, 0.1) - mean) * (Eigen::Vector2d(5.3, 0.1) - mean).transpose());
  cov /= w;
  EXPECT_NEAR(post.components[0].weight, w, 1e-12);
  EXPECT_NEAR((post.components[0].mean - mean).norm(), 0.0, 1e-12);
  EXPECT_NEAR((post.components[0].cov - cov).norm(), 0.0, 1e-12);
}

TEST(GmPhd, RejectsNonFiniteMeasurements) {
  const Model model(sensor());
  const Updater up(model, PhdConfig{});
  Z z;
  z.push_back(Eigen::Vector2d(1.0, std::nan("")));
  EXPECT_THROW(up.validate(z, 3), InputError);
}

// A small world: landmarks along a straight drive, noisy odometry; PHD-SLAM must beat dead reckoning and be
// deterministic whatever the thread count.
struct FilterRun {
  std::vector<Pose2, Eigen::aligned_allocator<Pose2>> estimates;
  double rmse = 0.0, dr_rmse = 0.0;
};

FilterRun run_filter(int threads, const std::string& likelihood) {
  set_thread_count(threads);
  UnicycleMotionConfig mc;
  mc.dt = 1.0;
  mc.sigma_v = 0.3;
  mc.sigma_omega = 3.0 * M_PI / 180.0;
  const UnicycleMotion motion(mc);
  RangeBearingConfig sc = sensor();
  sc.max_range = 8.0;
  sc.p_detect_inside = 0.9;
  sc.clutter_rate = 1.0;
  const Model model(sc);
  PhdConfig cfg;
  cfg.particles = 50;
  cfg.seed = 5;
  cfg.likelihood = likelihood;
  std::vector<Eigen::Vector2d> landmarks;
  for (int i = 0; i < 30; ++i) landmarks.emplace_back(2.0 * i, (i % 2 == 0 ? 3.0 : -3.0));
  RandomStream data(99);
  Pose2 truth(0, 0, 0), dr(0, 0, 0);
  PhdSlam<UnicycleMotion, Model> slam(motion, model, cfg, truth);
  FilterRun run;
  double se = 0.0, dr_se = 0.0;
  const Eigen::Vector2d u_true(1.0, 0.0);
  for (int k = 1; k <= 40; ++k) {
    truth = motion.predict(truth, u_true);
    const Eigen::Vector2d u =
        u_true + Eigen::Vector2d(mc.sigma_v * data.normal(), mc.sigma_omega * data.normal());
    dr = motion.predict(dr, u);
    Z z;
    for (const auto& m : landmarks) {
      if (model.in_field_of_view(truth, m) && data.uniform() < sc.p_detect_inside) {
        z.push_back(model.predict(truth, m) +
                    Eigen::Vector2d(sc.sigma_range * data.normal(), sc.sigma_bearing * data.normal()));
      }
    }
    const int n_c = data.poisson(sc.clutter_rate);
    for (int c = 0; c < n_c; ++c) z.emplace_back(data.uniform(0.0, sc.max_range), data.uniform(-M_PI, M_PI));
    slam.step(u, z);
    run.estimates.push_back(slam.pose());
    se += (slam.pose().head<2>() - truth.head<2>()).squaredNorm();
    dr_se += (dr.head<2>() - truth.head<2>()).squaredNorm();
  }
  run.rmse = std::sqrt(se / 40.0);
  run.dr_rmse = std::sqrt(dr_se / 40.0);
  set_thread_count(2);
  return run;
}

TEST(PhdSlam, BeatsDeadReckoningAndIsDeterministicAcrossThreadCounts) {
  for (const char* likelihood : {"empty_map", "single_feature", "poisson"}) {
    const FilterRun one = run_filter(1, likelihood);
    const FilterRun two = run_filter(2, likelihood);
    ASSERT_EQ(one.estimates.size(), two.estimates.size());
    for (std::size_t k = 0; k < one.estimates.size(); ++k)
      EXPECT_EQ(one.estimates[k], two.estimates[k]) << likelihood;
    std::printf("%s: rmse %.3f dead reckoning %.3f\n", likelihood, one.rmse, one.dr_rmse);
    EXPECT_TRUE(std::isfinite(one.rmse));
    // The empty-map weight of 002 (Eq. 15) is known to be weak with 003's small birth weight (digest 1.7
    // pitfall "poor memory"; 003 Table II: 21.5 m at N = 10), so only the single-feature and Poisson forms
    // must beat dead reckoning here.
    if (std::string(likelihood) == "empty_map") continue;
    EXPECT_LT(one.rmse, one.dr_rmse) << likelihood << " rmse " << one.rmse << " dead reckoning "
                                     << one.dr_rmse;
  }
}

}  // namespace
}  // namespace glmbslam::backend
