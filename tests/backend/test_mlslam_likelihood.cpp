// RFS measurement likelihood of paper 004 (Eq. 7) against brute-force enumeration of the associations, its
// marginals, and its equality with the vector least-squares cost (Eq. 4) when one association dominates.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <random>

#include "backend/mlslam/line_ml_slam.hpp"
#include "backend/mlslam/move_gains.hpp"
#include "backend/mlslam/scan_likelihood.hpp"
#include "backend/mlslam/scan_move_gain.hpp"
#include "backend/mlslam/smooth_stereo_detection.hpp"
#include "core/gaussian.hpp"
#include "mlslam_test_problem.hpp"
#include "stereo_test_support.hpp"

namespace glmbslam::backend {
namespace {

using test::Slam2D;

/// Eq. 7 summed over every association θ (injective partial maps measurement → landmark), with the p_D of
/// `detection` and the pairs of squared Mahalanobis distance ≤ `gate` (every pair by default);
/// beta(m, n) receives Σ_θ π_θ 1[θ(n) = m].
template <class Model, class Detection, class LandmarkList, class MeasurementSet>
double brute_force_eq7(const Model& model, const Detection& detection, const typename Model::Pose& x,
                       const LandmarkList& M, const MeasurementSet& Z, Eigen::MatrixXd* beta,
                       double gate = std::numeric_limits<double>::infinity()) {
  const std::size_t P = M.size(), J = Z.size();
  std::vector<double> pd(P);
  for (std::size_t p = 0; p < P; ++p) pd[p] = detection(model, x, M[p], model.predict(x, M[p]));
  std::vector<double> log_terms;
  std::vector<std::vector<int>> thetas;
  std::vector<int> theta(J, -1);  // measurement → landmark or −1 (clutter)
  std::vector<char> used(P, 0);
  std::function<void(std::size_t)> rec = [&](std::size_t j) {
    if (j == J) {
      double l = -model.clutter_rate();
      for (std::size_t n = 0; n < J; ++n) {
        if (theta[n] < 0) {
          l += model.log_clutter_intensity(Z[n]);
        } else {
          const auto r = model.residual(Z[n], model.predict(x, M[static_cast<std::size_t>(theta[n])]));
          l += std::log(pd[static_cast<std::size_t>(theta[n])]) + log_gaussian(r, model.noise());
        }
      }
      for (std::size_t p = 0; p < P; ++p)
        if (used[p] == 0) l += std::log(1.0 - pd[p]);
      log_terms.push_back(l);
      thetas.push_back(theta);
      return;
    }
    theta[j] = -1;
    rec(j + 1);
    for (std::size_t p = 0; p < P; ++p) {
      if (used[p] != 0) continue;
      if (mahalanobis_squared(model.residual(Z[j], model.predict(x, M[p])), model.noise()) > gate) continue;
      used[p] = 1;
      theta[j] = static_cast<int>(p);
      rec(j + 1);
      used[p] = 0;
      theta[j] = -1;
    }
  };
  rec(0);
  const double total = log_sum_exp(log_terms);
  *beta = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(J));
  for (std::size_t t = 0; t < thetas.size(); ++t)
    for (std::size_t n = 0; n < J; ++n)
      if (thetas[t][n] >= 0)
        (*beta)(thetas[t][n], static_cast<Eigen::Index>(n)) += std::exp(log_terms[t] - total);
  return total;
}

RangeBearingModel ambiguous_model() {
  RangeBearingConfig c;
  c.sigma_range = 0.3;
  c.sigma_bearing = 0.1;
  c.max_range = 5.0;
  c.half_fov = 1.0;
  c.p_detect_inside = 0.8;
  c.clutter_rate = 2.0;
  return RangeBearingModel(c);
}

TEST(MlSlamLikelihood, EqualsBruteForceEnumerationOfEq7) {
  const RangeBearingModel model = ambiguous_model();
  const SmoothDetection2D detection(model, 0.2, 0.05);
  const Pose2 x(0.1, -0.2, 0.05);
  // three landmarks close together (ambiguous), one near the range border, one near the bearing border
  const Slam2D::LandmarkList M{{3.0, 0.1}, {3.2, -0.2}, {2.9, 0.4}, {4.95, 0.0}, {1.5, 1.2}};
  const Slam2D::MeasurementSet Z{{3.0, 0.1}, {3.3, -0.05}, {2.2, 0.3}, {4.8, 0.05}, {1.9, 0.9}};
  ScanLikelihoodOptions o;
  o.gate = 1e9;
  o.max_assignments = 100000;
  o.assignment_log_gap = 1e9;
  const ScanAssociation s = evaluate_scan(model, detection, x, M, Z, o);
  Eigen::MatrixXd beta;
  const double expected = brute_force_eq7(model, detection, x, M, Z, &beta);
  EXPECT_NEAR(s.log_likelihood, expected, 1e-9);
  Eigen::MatrixXd got = Eigen::MatrixXd::Zero(beta.rows(), beta.cols());
  for (const auto& b : s.betas) got(b.landmark, b.measurement) += b.beta;
  EXPECT_LT((got - beta).cwiseAbs().maxCoeff(), 1e-9);
  // every measurement's responsibilities (landmarks + clutter) sum to at most 1, and some are shared
  EXPECT_LE(got.colwise().sum().maxCoeff(), 1.0 + 1e-12);
  EXPECT_GT((got.array() > 0.05 && got.array() < 0.95).count(), 2);
}

/// evaluate_scan with every ranked assignment and `gate` against brute force over the gated associations;
/// returns the marginals β (landmark × measurement).
template <class Model, class Detection, class LandmarkList, class MeasurementSet>
Eigen::MatrixXd expect_gated_scan_equals_brute_force(const Model& model, const Detection& detection,
                                                     const typename Model::Pose& x, const LandmarkList& M,
                                                     const MeasurementSet& Z, double gate) {
  ScanLikelihoodOptions o;
  o.gate = gate;
  o.max_assignments = 100000;
  o.assignment_log_gap = 1e9;
  const ScanAssociation s = evaluate_scan(model, detection, x, M, Z, o);
  Eigen::MatrixXd beta;
  EXPECT_NEAR(s.log_likelihood, brute_force_eq7(model, detection, x, M, Z, &beta, gate), 1e-9);
  Eigen::MatrixXd got = Eigen::MatrixXd::Zero(beta.rows(), beta.cols());
  for (const auto& b : s.betas) got(b.landmark, b.measurement) += b.beta;
  EXPECT_LT((got - beta).cwiseAbs().maxCoeff(), 1e-9);
  return got;
}

TEST(MlSlamLikelihood, OneDimensionalScanEqualsBruteForceEnumerationOfEq7) {
  // paper 004's 1D sensor: two close landmarks (ambiguous), one at each smooth border of the interval
  LineSensorConfig c;
  c.variance = 0.04;
  c.p_detect_inside = 0.8;
  c.clutter_rate = 1.5;
  const LineMeasurementModel model(c);
  const SmoothDetection1D detection(model, 0.1);
  const LinePose x = LinePose::Constant(0.3);
  LineMlSlam::LandmarkList M;
  for (double m : {3.0, 3.2, 0.85, 6.25}) M.push_back(LinePose::Constant(m));
  LineMlSlam::MeasurementSet Z;
  for (double z : {2.75, 2.95, 0.5, 5.8, 1.7}) Z.push_back(LinePose::Constant(z));
  const Eigen::MatrixXd got = expect_gated_scan_equals_brute_force(model, detection, x, M, Z, 1e9);
  EXPECT_GT((got.array() > 0.05 && got.array() < 0.95).count(), 2);  // the close pair shares its measurements
  // p_D is half its inside value at each end of the interval
  EXPECT_NEAR(detection(model, x, LinePose::Constant(0.3 + c.min_range), LinePose::Constant(c.min_range)),
              0.4, 1e-6);
  EXPECT_NEAR(detection(model, x, LinePose::Constant(0.3 + c.max_range), LinePose::Constant(c.max_range)),
              0.4, 1e-6);
}

/// evaluate_scan looks at a landmark's measurements only within √(gate R_00) of ẑ_0: with a finite gate it
/// must give the brute-force sum over the gated associations, pairs outside that window included in the scan.
TEST(MlSlamLikelihood, GatedScanEqualsBruteForceOverTheGatedAssociations) {
  {
    const RangeBearingModel model = ambiguous_model();
    const SmoothDetection2D detection(model, 0.2, 0.05);
    const Pose2 x(0.1, -0.2, 0.05);
    const Slam2D::LandmarkList M{{3.0, 0.1}, {3.2, -0.2}, {2.9, 0.4}, {4.95, 0.0}, {1.5, 1.2}, {1.0, -0.5}};
    const Slam2D::MeasurementSet Z{{3.0, 0.1},  {3.3, -0.05}, {2.2, 0.3},
                                   {4.8, 0.05}, {1.9, 0.9},   {1.1, -0.6}};
    expect_gated_scan_equals_brute_force(model, detection, x, M, Z, 9.0);
  }
  {
    StereoMeasurementConfig c;
    c.pixel_sigma = 2.0;
    c.clutter_rate = 3.0;
    const StereoMeasurementModel model(test::kitti_calibration(), c);
    const SmoothStereoDetection detection(model, 0.0, 0.0);
    const Pose3 x = Pose3::Identity();
    // landmarks in pairs a few pixels apart (shared measurements), one pair sharing v but not u_L
    std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> M{
        {1.0, 0.5, 12.0},   {1.02, 0.52, 12.1}, {-3.0, 1.0, 20.0},
        {-2.98, 1.0, 19.0}, {4.0, 0.5, 12.0},   {6.0, 0.5, 12.0}};
    std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> Z;
    for (const auto& m : M) Z.push_back(model.predict(x, m) + Eigen::Vector3d(1.5, -1.0, 0.5));
    Z.push_back({600.0, 100.0, 580.0});  // clutter
    const Eigen::MatrixXd beta = expect_gated_scan_equals_brute_force(model, detection, x, M, Z, 16.0);
    EXPECT_GT((beta.array() > 0.05 && beta.array() < 0.95).count(), 2);  // ambiguous pairs exist
  }
}

TEST(MlSlamLikelihood, GatedTruncationIsALowerBoundCloseToTheExactSum) {
  const RangeBearingModel model = ambiguous_model();
  const SmoothDetection2D detection(model, 0.2, 0.05);
  const Pose2 x(0.0, 0.0, 0.0);
  const Slam2D::LandmarkList M{{3.0, 0.1}, {3.2, -0.2}, {2.9, 0.4}};
  const Slam2D::MeasurementSet Z{{3.0, 0.1}, {3.3, -0.05}, {2.2, 0.3}};
  ScanLikelihoodOptions exact;
  exact.gate = 1e9;
  exact.max_assignments = 100000;
  exact.assignment_log_gap = 1e9;
  ScanLikelihoodOptions truncated;  // defaults: gate 16, 50 assignments, gap 9.2
  const double l_exact = evaluate_scan(model, detection, x, M, Z, exact).log_likelihood;
  const double l_trunc = evaluate_scan(model, detection, x, M, Z, truncated).log_likelihood;
  EXPECT_LE(l_trunc, l_exact + 1e-12);
  EXPECT_GT(l_trunc, l_exact - 1e-3);
}

// The birth bound of move_gains.hpp: log p(Z | x, M ∪ {a}) − log p(Z | x, M) (both by brute force over the
// gated associations) never exceeds it, and equals it when every measurement a gates with is pure clutter
// under M (no landmark of M gates with it).
TEST(MlSlamLikelihood, BirthBoundIsAnUpperBoundOnTheBruteForceGain) {
  const RangeBearingModel model = ambiguous_model();
  const SmoothDetection2D detection(model, 0.2, 0.05);
  const Pose2 x(0.1, -0.2, 0.05);
  const Slam2D::LandmarkList M{{3.0, 0.1}, {3.2, -0.2}, {2.9, 0.4}, {4.95, 0.0}, {1.5, 1.2}};
  const Slam2D::MeasurementSet Z{{3.0, 0.1}, {3.3, -0.05}, {2.2, 0.3}, {4.8, 0.05}, {1.9, 0.9}, {1.2, -0.6}};
  const double gate = 9.0;
  const GatedDensity<RangeBearingModel> g(model, gate);
  Eigen::MatrixXd beta;
  const double l0 = brute_force_eq7(model, detection, x, M, Z, &beta, gate);
  int tight = 0;
  // candidates on the shared measurements, between them, on the clutter measurement, and out of view
  const Slam2D::LandmarkList candidates{{3.05, 0.05}, {3.1, -0.1}, {2.5, 0.45}, {1.25, -0.55},
                                        {1.3, -0.4},  {4.9, 0.1},  {-3.0, 0.0}};
  for (const auto& a : candidates) {
    Slam2D::LandmarkList Ma = M;
    Ma.push_back(a);
    const double gain = brute_force_eq7(model, detection, x, Ma, Z, &beta, gate) - l0;
    const double bound = log_birth_ratio_bound(model, detection, g, x, a, Z);
    EXPECT_LE(gain, bound + 1e-9);
    // measurements a gates with that no landmark of M gates with: the bound is the exact gain
    bool clutter_only = true;
    for (const auto& z : Z) {
      if (mahalanobis_squared(model.residual(z, model.predict(x, a)), model.noise()) > gate) continue;
      for (const auto& m : M)
        clutter_only =
            clutter_only && mahalanobis_squared(model.residual(z, model.predict(x, m)), model.noise()) > gate;
    }
    if (clutter_only) {
      EXPECT_NEAR(gain, bound, 1e-9);
      ++tight;
    }
  }
  EXPECT_GE(tight, 2);  // the clutter measurement's candidates and the one out of view
}

// A cardinality move's Δl from the blocks it touches (scan_move_gain.hpp) against the whole scan evaluated
// before and after: deaths, merges, births and mixed moves on random scans with blocks of every size, and
// against brute-force enumeration of Eq. 7 on a small one.
TEST(MlSlamLikelihood, MoveGainFromTheTouchedBlocksEqualsTheWholeScanDifference) {
  const RangeBearingModel model = ambiguous_model();
  const SmoothDetection2D detection(model, 0.2, 0.05);
  ScanLikelihoodOptions o;
  o.gate = 9.0;
  o.max_assignments = 1000;
  o.assignment_log_gap = 1e9;
  o.marginals = false;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> range(0.5, 5.5), bearing(-1.2, 1.2), jitter(-0.15, 0.15);
  const Pose2 x(0.3, 0.1, -0.1);
  int nontrivial = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Slam2D::LandmarkList M;
    Slam2D::MeasurementSet Z;
    for (int k = 0; k < 25; ++k) {
      const double r = range(rng), b = bearing(rng);
      const Eigen::Vector2d m = x.head<2>() + Eigen::Rotation2Dd(x(2) + b) * Eigen::Vector2d(r, 0.0);
      M.push_back(m);
      if (k % 4 != 0) Z.push_back(model.predict(x, m) + Eigen::Vector2d(jitter(rng), 0.3 * jitter(rng)));
    }
    for (int k = 0; k < 5; ++k) Z.push_back(Eigen::Vector2d(range(rng), bearing(rng)));  // clutter
    const double l0 = evaluate_scan(model, detection, x, M, Z, o).log_likelihood;
    const int a = trial % 25, b = (trial * 7 + 3) % 25;
    const Slam2D::LandmarkList born{M[static_cast<std::size_t>(b)] +
                                    Eigen::Vector2d(jitter(rng), jitter(rng))};
    const std::vector<std::pair<std::vector<int>, Slam2D::LandmarkList>> moves{
        {{a}, {}},                                                                            // death
        {{a, b}, {0.5 * (M[static_cast<std::size_t>(a)] + M[static_cast<std::size_t>(b)])}},  // merge
        {{}, born},                                                                           // birth
        {{b}, born}};                                                                         // replace
    for (const auto& [removed, added] : moves) {
      Slam2D::LandmarkList after;
      for (std::size_t p = 0; p < M.size(); ++p)
        if (std::find(removed.begin(), removed.end(), static_cast<int>(p)) == removed.end())
          after.push_back(M[p]);
      for (const auto& m : added) after.push_back(m);
      const double whole = evaluate_scan(model, detection, x, after, Z, o).log_likelihood - l0;
      const double gain = scan_move_gain(model, detection, x, M, removed, added, Z, o);
      EXPECT_NEAR(gain, whole, 1e-9 * (1.0 + std::abs(whole))) << "trial " << trial;
      if (std::abs(whole) > 1e-3) ++nontrivial;
    }
  }
  EXPECT_GT(nontrivial, 100);  // the moves do change l: the test compares real gains

  // small enough for brute force: remove landmark 1, add one between measurements 1 and 2
  const Pose2 y(0.1, -0.2, 0.05);
  const Slam2D::LandmarkList M{{3.0, 0.1}, {3.2, -0.2}, {2.9, 0.4}, {4.95, 0.0}, {1.5, 1.2}};
  const Slam2D::MeasurementSet Z{{3.0, 0.1}, {3.3, -0.05}, {2.2, 0.3}, {4.8, 0.05}, {1.9, 0.9}, {1.2, -0.6}};
  const Slam2D::LandmarkList added{{2.7, 0.1}};
  Slam2D::LandmarkList after{M[0], M[2], M[3], M[4], added[0]};
  Eigen::MatrixXd beta;
  const double brute = brute_force_eq7(model, detection, y, after, Z, &beta, o.gate) -
                       brute_force_eq7(model, detection, y, M, Z, &beta, o.gate);
  EXPECT_NEAR(scan_move_gain(model, detection, y, M, {1}, added, Z, o), brute, 1e-9);
}

// With one dominant association (well separated landmarks, small noise, constant p_D) the log-likelihood
// differs from −½ of the vector cost of Eq. 4 by a constant: changes of the estimate change both equally.
TEST(MlSlamLikelihood, OneDominantAssociationEqualsTheVectorCost) {
  const auto p = test::make_problem(20, 6, 0.9, 0.0, 3);
  MlSlamConfig config;
  config.border_range_m = 1e-3;
  const Slam2D slam(p.motion, p.model, config);
  const RangeBearingModel& model = p.model;
  const auto vector_cost = [&](const Slam2D::PoseList& x, const Slam2D::LandmarkList& m) {
    double c = 0.0;
    for (std::size_t k = 1; k < x.size(); ++k) {
      const auto d = UnicycleMotion::local(x[k], p.motion.predict(x[k - 1], p.controls[k]));
      const auto P = p.motion.process_noise(x[k - 1], p.controls[k]);
      c += mahalanobis_squared(d, P) + std::log((2.0 * M_PI * P).determinant());
    }
    // measurements with their true sources: the nearest predicted landmark (no clutter here)
    for (std::size_t k = 0; k < x.size(); ++k) {
      for (const auto& z : p.scans[k]) {
        double best = 1e300;
        for (const auto& l : m)
          best =
              std::min(best, mahalanobis_squared(model.residual(z, model.predict(x[k], l)), model.noise()));
        c += best;
      }
    }
    return -0.5 * c;
  };
  Slam2D::PoseList x = p.truth;
  Slam2D::LandmarkList m = p.landmarks;
  const double l0 = slam.log_likelihood(x, p.controls, p.scans, m), v0 = vector_cost(x, m);
  x[5](0) += 0.01;
  x[9](2) += 0.004;
  m[2](1) -= 0.01;
  const double l1 = slam.log_likelihood(x, p.controls, p.scans, m), v1 = vector_cost(x, m);
  EXPECT_GT(std::abs(l1 - l0), 1.0);  // the perturbation matters
  EXPECT_NEAR(l1 - l0, v1 - v0, 1e-6 * std::abs(l1 - l0));
}

/// A block of one landmark and one measurement skips Murty; it must give what rank_associations and
/// log_sum_exp give, bit for bit, including ties, a certain detection (log_miss = −∞), the gap and one
/// assignment only.
TEST(MlSlamLikelihood, OnePairBlockEqualsMurtyBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-30.0, 10.0);
  std::vector<std::pair<double, double>> cases{{-2.0, -2.0}, {1.0, kLogZero},  {-25.0, 0.0},
                                               {0.0, -25.0}, {3.0, 3.0 - 9.2}, {-1.0, -1.0 - 9.2 - 1e-12}};
  for (int k = 0; k < 2000; ++k) cases.emplace_back(u(rng), k % 50 == 0 ? kLogZero : u(rng));
  for (const int max_assignments : {1, 2, 50}) {
    for (const double gap : {0.0, 9.2, 1e9}) {
      MurtyOptions murty;
      murty.max_solutions = static_cast<std::size_t>(max_assignments);
      murty.max_cost_gap = gap;
      for (const auto& [gain, log_miss] : cases) {
        Eigen::MatrixXd log_detect(1, 1);
        log_detect(0, 0) = gain;
        Eigen::VectorXd miss(1);
        miss(0) = log_miss;
        const auto hyps = rank_associations(log_detect, miss, murty);
        std::vector<double> lw;
        for (const auto& h : hyps) lw.push_back(h.log_weight);
        const double expected = log_sum_exp(lw);
        double expected_beta = 0.0;
        for (const auto& h : hyps)
          if (h.measurement_of[0] >= 0) expected_beta += std::exp(h.log_weight - expected);
        std::vector<double> betas;
        const double got = one_pair_block(gain, log_miss, murty, true, [&](double b) { betas.push_back(b); });
        EXPECT_EQ(got, expected) << gain << " " << log_miss;
        ASSERT_EQ(betas.size(), expected_beta > 0.0 ? 1U : 0U) << gain << " " << log_miss;
        if (!betas.empty()) {
          EXPECT_EQ(betas[0], expected_beta) << gain << " " << log_miss;
        }
      }
    }
  }
}

}  // namespace
}  // namespace glmbslam::backend
