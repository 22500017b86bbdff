#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "core/random.hpp"
#include "eval/ospa.hpp"

namespace glmbslam::eval {
namespace {

/// OSPA by enumerating every injection of the smaller set into the larger (definition, Schuhmacher et al. eq.
/// (3)).
double ospa_brute(const PointSet& x, const PointSet& y, double c, double p) {
  const bool swap = x.cols() > y.cols();
  const PointSet& a = swap ? y : x;  // smaller, size m
  const PointSet& b = swap ? x : y;  // larger, size n
  const int m = static_cast<int>(a.cols()), n = static_cast<int>(b.cols());
  if (n == 0) return 0.0;
  std::vector<int> perm(static_cast<size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {  // every permutation of b; the first m entries give an injection (duplicates are harmless)
    double s = 0.0;
    for (int i = 0; i < m; ++i)
      s += std::pow(std::min(c, (a.col(i) - b.col(perm[static_cast<size_t>(i)])).norm()), p);
    best = std::min(best, s);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return std::pow((best + std::pow(c, p) * (n - m)) / n, 1.0 / p);
}

/// GOSPA (α = 2) by enumerating every partial assignment γ, using the uncut distance (Rahmathullah et al.
/// Prop. 1).
void gospa_enumerate(const PointSet& x, const PointSet& y, double c, double p, int i, std::vector<char>& used,
                     double loc, int assigned, double& best) {
  if (i == x.cols()) {
    const double v = loc + 0.5 * std::pow(c, p) * static_cast<double>(x.cols() + y.cols() - 2 * assigned);
    best = std::min(best, v);
    return;
  }
  gospa_enumerate(x, y, c, p, i + 1, used, loc, assigned, best);
  for (int j = 0; j < y.cols(); ++j) {
    if (used[static_cast<size_t>(j)]) continue;
    used[static_cast<size_t>(j)] = 1;
    gospa_enumerate(x, y, c, p, i + 1, used, loc + std::pow((x.col(i) - y.col(j)).norm(), p), assigned + 1,
                    best);
    used[static_cast<size_t>(j)] = 0;
  }
}

double gospa_brute(const PointSet& x, const PointSet& y, double c, double p) {
  std::vector<char> used(static_cast<size_t>(y.cols()), 0);
  double best = std::numeric_limits<double>::infinity();
  gospa_enumerate(x, y, c, p, 0, used, 0.0, 0, best);
  return std::pow(best, 1.0 / p);
}

PointSet random_set(RandomStream& rng, int dim, int n) {
  PointSet s(dim, n);
  for (int j = 0; j < n; ++j)
    for (int d = 0; d < dim; ++d) s(d, j) = rng.uniform(0.0, 10.0);
  return s;
}

TEST(Ospa, MatchesBruteForceIn2DAnd3D) {
  RandomStream rng(31);
  for (int trial = 0; trial < 300; ++trial) {
    const int dim = trial % 2 == 0 ? 2 : 3;
    const PointSet x = random_set(rng, dim, static_cast<int>(rng.index(6)));
    const PointSet y = random_set(rng, dim, static_cast<int>(rng.index(6)));
    const double c = rng.uniform(0.5, 8.0);
    const double p = trial % 3 == 0 ? 1.0 : (trial % 3 == 1 ? 2.0 : 3.5);
    const OspaResult r = ospa(x, y, c, p);
    EXPECT_NEAR(r.distance, ospa_brute(x, y, c, p), 1e-9) << "trial " << trial;
    EXPECT_NEAR(r.distance, ospa(y, x, c, p).distance, 1e-9);  // symmetric
    EXPECT_LE(r.distance, c + 1e-12);
    EXPECT_NEAR(std::pow(r.distance, p), std::pow(r.localisation, p) + std::pow(r.cardinality, p), 1e-9);
  }
}

TEST(Gospa, MatchesBruteForceIn2DAnd3D) {
  RandomStream rng(32);
  for (int trial = 0; trial < 300; ++trial) {
    const int dim = trial % 2 == 0 ? 2 : 3;
    const PointSet x = random_set(rng, dim, static_cast<int>(rng.index(6)));
    const PointSet y = random_set(rng, dim, static_cast<int>(rng.index(6)));
    const double c = rng.uniform(0.5, 8.0);
    const double p = trial % 3 == 0 ? 1.0 : (trial % 3 == 1 ? 2.0 : 3.5);
    const GospaResult r = gospa(x, y, c, p);
    EXPECT_NEAR(r.distance, gospa_brute(x, y, c, p), 1e-9) << "trial " << trial;
    EXPECT_NEAR(std::pow(r.distance, p), r.localisation + r.missed + r.false_, 1e-9);
    EXPECT_EQ(r.missed_count + r.assigned_count, x.cols());
    EXPECT_EQ(r.false_count + r.assigned_count, y.cols());
  }
}

TEST(Ospa, EmptySetConventions) {
  const PointSet empty(0, 0);
  PointSet one(2, 1);
  one << 1.0, 2.0;
  EXPECT_DOUBLE_EQ(ospa(empty, empty, 5.0, 2.0).distance, 0.0);
  EXPECT_DOUBLE_EQ(ospa(empty, one, 5.0, 2.0).distance, 5.0);
  EXPECT_DOUBLE_EQ(ospa(one, empty, 5.0, 1.0).distance, 5.0);
  EXPECT_DOUBLE_EQ(gospa(empty, empty, 5.0, 2.0).distance, 0.0);
  // One missed object: (c^p / 2)^(1/p).
  EXPECT_NEAR(gospa(one, empty, 4.0, 2.0).distance, std::sqrt(8.0), 1e-12);
  EXPECT_EQ(gospa(one, empty, 4.0, 2.0).missed_count, 1);
  EXPECT_EQ(gospa(empty, one, 4.0, 2.0).false_count, 1);
}

TEST(Ospa, HandComputed) {
  // X = {(0,0), (10,0)}, Y = {(1,0)}; c = 5, p = 1: match (0,0)-(1,0) at 1, one unmatched at cost c:
  // OSPA = (1 + 5) / 2 = 3. GOSPA: 1 + 5/2 (one missed) = 3.5, localisation 1, missed 2.5.
  const PointSet x = point_set_from({Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 0)});
  const PointSet y = point_set_from({Eigen::Vector2d(1, 0)});
  EXPECT_NEAR(ospa(x, y, 5.0, 1.0).distance, 3.0, 1e-12);
  const GospaResult g = gospa(x, y, 5.0, 1.0);
  EXPECT_NEAR(g.distance, 3.5, 1e-12);
  EXPECT_NEAR(g.localisation, 1.0, 1e-12);
  EXPECT_NEAR(g.missed, 2.5, 1e-12);
  EXPECT_NEAR(g.false_, 0.0, 1e-12);
  // A pair farther apart than c is a missed plus a false object, not a localisation error.
  const PointSet far = point_set_from({Eigen::Vector2d(20, 0)});
  const GospaResult h = gospa(point_set_from({Eigen::Vector2d(0, 0)}), far, 5.0, 2.0);
  EXPECT_EQ(h.assigned_count, 0);
  EXPECT_EQ(h.missed_count, 1);
  EXPECT_EQ(h.false_count, 1);
  EXPECT_NEAR(h.distance, 5.0, 1e-12);
}

TEST(Ospa, BadArguments) {
  const PointSet a = PointSet::Zero(2, 1), b = PointSet::Zero(3, 1);
  EXPECT_THROW(ospa(a, b, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ospa(a, a, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(gospa(a, a, 1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(point_set_from({Eigen::Vector2d(0, 0), Eigen::Vector3d(0, 0, 0)}), std::invalid_argument);
}

}  // namespace
}  // namespace glmbslam::eval
