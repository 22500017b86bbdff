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

// Sampling rows {2, 0} of a prepared table (with skip_repeats) gives the same distinct solutions, in the same
// order, as sampling a table built from those rows alone, for short chains (owner tests) and long ones
// (counts of taken columns); the caller's stream advances identically.
TEST(GibbsSampler, RowSubsetMatchesSubTable) {
  const AssociationTable full = make_table();
  const int rows[2] = {2, 0};
  AssociationTable sub;
  sub.reset(full.num_measurements());
  for (int r : rows) {
    for (int e = full.row_begin(r); e < full.row_end(r); ++e) sub.add(full.column(e), full.log_eta(e));
    sub.end_row();
  }
  for (int sweeps : {0, 1, 3, 4, 50, 5000}) {
    RandomStream rng_a(9, sweeps), rng_b(9, sweeps);
    GibbsWorkspace ws_a, ws_b;
    std::vector<int> a, b;
    const int count_a = gibbs_sample(sub, sweeps, rng_a, ws_a, a);
    const int count_b = gibbs_sample(full, rows, 2, sweeps, rng_b, ws_b, b, true);
    EXPECT_EQ(count_a, sweeps + 1);
    EXPECT_LE(count_b, count_a);
    const int distinct_a = unique_solutions(a, 2, count_a);
    const int distinct_b = unique_solutions(b, 2, count_b);
    EXPECT_EQ(distinct_a, distinct_b) << sweeps;
    EXPECT_EQ(a, b) << sweeps;
    EXPECT_EQ(rng_a.uniform(), rng_b.uniform());
  }
}

}  // namespace
}  // namespace glmbslam::backend
