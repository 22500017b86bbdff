// Murty's k-best assignments against brute-force enumeration.
#include <algorithm>
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "backend/rbpf/murty.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// All complete assignments of an n×m matrix (n ≤ m) avoiding +∞, sorted by cost.
std::vector<RankedAssignment> brute_force(const Eigen::MatrixXd& cost) {
  std::vector<RankedAssignment> all;
  const int n = static_cast<int>(cost.rows()), m = static_cast<int>(cost.cols());
  std::vector<int> assign(static_cast<std::size_t>(n));
  std::vector<bool> used(static_cast<std::size_t>(m), false);
  std::function<void(int, double)> rec = [&](int i, double c) {
    if (i == n) {
      all.push_back({assign, c});
      return;
    }
    for (int j = 0; j < m; ++j) {
      if (used[static_cast<std::size_t>(j)] || cost(i, j) == kInf) continue;
      used[static_cast<std::size_t>(j)] = true;
      assign[static_cast<std::size_t>(i)] = j;
      rec(i + 1, c + cost(i, j));
      used[static_cast<std::size_t>(j)] = false;
    }
  };
  rec(0, 0.0);
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.cost < b.cost; });
  return all;
}

Eigen::MatrixXd random_cost(RandomStream& rng, int n, int m, double p_forbidden) {
  Eigen::MatrixXd c(n, m);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) c(i, j) = rng.uniform() < p_forbidden ? kInf : rng.uniform(-5.0, 10.0);
  return c;
}

TEST(Murty, EqualsBruteForceRankingOnSmallMatrices) {
  RandomStream rng(7);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng.index(4));
    const int m = n + static_cast<int>(rng.index(3));
    const Eigen::MatrixXd cost = random_cost(rng, n, m, trial % 2 == 0 ? 0.0 : 0.3);
    const auto expected = brute_force(cost);
    MurtyOptions all;
    all.max_solutions = 10000;
    const auto got = murty_k_best(cost, all);
    ASSERT_EQ(got.size(), expected.size()) << "trial " << trial;
    for (std::size_t t = 0; t < got.size(); ++t) {
      EXPECT_NEAR(got[t].cost, expected[t].cost, 1e-9) << "trial " << trial << " rank " << t;
      // Continuous random costs: no ties, so the assignments themselves must match.
      EXPECT_EQ(got[t].row_to_col, expected[t].row_to_col) << "trial " << trial << " rank " << t;
      double c = 0.0;
      for (int i = 0; i < n; ++i) c += cost(i, got[t].row_to_col[static_cast<std::size_t>(i)]);
      EXPECT_NEAR(c, got[t].cost, 1e-9);
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

TEST(Murty, StopsAfterKOrBelowTheRatio) {
  RandomStream rng(11);
  const Eigen::MatrixXd cost = random_cost(rng, 4, 6, 0.0);
  const auto expected = brute_force(cost);
  MurtyOptions k5;
  k5.max_solutions = 5;
  const auto five = murty_k_best(cost, k5);
  ASSERT_EQ(five.size(), 5u);
  for (std::size_t t = 0; t < 5; ++t) EXPECT_NEAR(five[t].cost, expected[t].cost, 1e-9);
  MurtyOptions gap;
  gap.max_solutions = 10000;
  gap.max_cost_gap = 3.0;
  const auto within = murty_k_best(cost, gap);
  const auto n_within = std::count_if(expected.begin(), expected.end(),
                                      [&](const auto& a) { return a.cost - expected[0].cost <= 3.0; });
  EXPECT_EQ(static_cast<long>(within.size()), n_within);
}

TEST(Murty, DegenerateInputs) {
  EXPECT_EQ(murty_k_best(Eigen::MatrixXd(0, 3)).size(), 1u);
  Eigen::MatrixXd infeasible(2, 2);
  infeasible << 1, kInf, 2, kInf;
  EXPECT_TRUE(murty_k_best(infeasible).empty());
  EXPECT_THROW(murty_k_best(Eigen::MatrixXd::Zero(3, 2)), std::invalid_argument);
  Eigen::MatrixXd nan = Eigen::MatrixXd::Zero(1, 1);
  nan(0, 0) = std::nan("");
  EXPECT_THROW(murty_k_best(nan), std::invalid_argument);
}

TEST(Murty, RankedAssociationsEqualEnumerationOfAllDataAssociations) {
  RandomStream rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const int M = 1 + static_cast<int>(rng.index(3));
    const int J = static_cast<int>(rng.index(4));
    Eigen::MatrixXd log_detect(M, J);
    for (int i = 0; i < M; ++i)
      for (int j = 0; j < J; ++j) log_detect(i, j) = rng.uniform() < 0.3 ? -kInf : rng.uniform(-6.0, 3.0);
    Eigen::VectorXd log_miss(M);
    for (int i = 0; i < M; ++i) log_miss(i) = std::log(rng.uniform(0.05, 0.9));
    // Enumerate φ: each landmark missed or one distinct measurement.
    std::vector<std::pair<double, std::vector<int>>> all;
    std::vector<int> phi(static_cast<std::size_t>(M));
    std::function<void(int, double)> rec = [&](int i, double lw) {
      if (i == M) {
        all.emplace_back(lw, phi);
        return;
      }
      phi[static_cast<std::size_t>(i)] = -1;
      rec(i + 1, lw + log_miss(i));
      for (int j = 0; j < J; ++j) {
        if (log_detect(i, j) == -kInf || std::find(phi.begin(), phi.begin() + i, j) != phi.begin() + i)
          continue;
        phi[static_cast<std::size_t>(i)] = j;
        rec(i + 1, lw + log_detect(i, j));
      }
    };
    rec(0, 0.0);
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    MurtyOptions o;
    o.max_solutions = 100000;
    const auto ranked = rank_associations(log_detect, log_miss, o);
    ASSERT_EQ(ranked.size(), all.size());
    for (std::size_t t = 0; t < all.size(); ++t) {
      EXPECT_NEAR(ranked[t].log_weight, all[t].first, 1e-9);
      EXPECT_EQ(ranked[t].measurement_of, all[t].second);
    }
    // The paper's stop rule: keep hypotheses at least 1e-3 as likely as the best.
    MurtyOptions paper;
    paper.max_solutions = 50;
    paper.max_cost_gap = -std::log(1e-3);
    const auto kept = rank_associations(log_detect, log_miss, paper);
    const auto n_kept = std::min<long>(50, std::count_if(all.begin(), all.end(), [&](const auto& a) {
                                         return a.first - all[0].first >= std::log(1e-3);
                                       }));
    EXPECT_EQ(static_cast<long>(kept.size()), n_kept);
  }
}

}  // namespace
}  // namespace glmbslam::backend
