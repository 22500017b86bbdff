// The Gibbs sampler's empirical distribution matches the exactly enumerated stationary distribution
// π(γ) ∝ Π_i η_i(γ_i) over valid assignments (each measurement used at most once).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "backend/glmb/gibbs_sampler.hpp"
#include "core/log_math.hpp"

namespace glmbslam::backend {
namespace {

// 3 rows, 3 measurements; row 2 has no entry for z_3 (gated out), row 1 has no dead entry (p_S = 1).
AssociationTable make_table() {
  AssociationTable t;
  t.reset(3);
  const double l[3][5] = {{0.2, 0.5, 1.5, 0.3, 0.1}, {-1, 0.4, 1.0, 1.2, 0.6}, {0.9, 0.3, 0.8, 2.0, -1}};
  for (int i = 0; i < 3; ++i) {
    for (int c = 0; c < 5; ++c) {
      if (l[i][c] < 0) continue;
      t.add(c - 1, std::log(l[i][c]));
    }
    t.end_row();
  }
  return t;
}

TEST(GibbsSampler, EmpiricalDistributionMatchesExactEnumeration) {
  const AssociationTable table = make_table();
  // exact distribution
  std::map<std::vector<int>, double> exact;
  std::vector<double> logs;
  for (int a = -1; a <= 3; ++a)
    for (int b = -1; b <= 3; ++b)
      for (int c = -1; c <= 3; ++c) {
        if ((a > 0 && (a == b || a == c)) || (b > 0 && b == c)) continue;
        const int g[3] = {a, b, c};
        const double lw = table.log_weight(g);
        if (lw == kLogZero) continue;
        exact[{a, b, c}] = lw;
        logs.push_back(lw);
      }
  const double z = log_sum_exp(logs);
  ASSERT_GT(exact.size(), 20u);
  RandomStream rng(42, 0);
  GibbsWorkspace ws;
  std::vector<int> samples;
  const int sweeps = 200000;
  const int count = gibbs_sample(table, sweeps, rng, ws, samples);
  ASSERT_EQ(count, sweeps + 1);
  std::map<std::vector<int>, double> empirical;
  for (int s = 1; s < count; ++s) {  // skip the initial state
    std::vector<int> g(samples.begin() + 3 * s, samples.begin() + 3 * s + 3);
    ASSERT_TRUE(exact.count(g)) << "sampler produced an invalid assignment";
    empirical[g] += 1.0 / sweeps;
  }
  double tv = 0.0;
  for (const auto& [g, lw] : exact) tv += std::abs(std::exp(lw - z) - empirical[g]);
  tv *= 0.5;
  EXPECT_LT(tv, 0.02);
}

TEST(GibbsSampler, UniqueSolutionsAndEmptyTable) {
  const AssociationTable table = make_table();
  RandomStream rng(1, 0);
  GibbsWorkspace ws;
  std::vector<int> samples;
  const int count = gibbs_sample(table, 1000, rng, ws, samples);
  const int distinct = unique_solutions(samples, 3, count);
  EXPECT_GT(distinct, 10);
  EXPECT_EQ(samples.size(), static_cast<std::size_t>(3 * distinct));
  for (int a = 0; a < distinct; ++a)
    for (int b = a + 1; b < distinct; ++b)
      EXPECT_FALSE(std::equal(samples.begin() + 3 * a, samples.begin() + 3 * a + 3, samples.begin() + 3 * b));
  AssociationTable empty;
  empty.reset(2);
  std::vector<int> none;
  const int c0 = gibbs_sample(empty, 0, rng, ws, none);
  EXPECT_EQ(unique_solutions(none, 0, c0), 1);
}

}  // namespace
}  // namespace glmbslam::backend
