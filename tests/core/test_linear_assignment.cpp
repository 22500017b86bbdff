#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "core/linear_assignment.hpp"
#include "core/random.hpp"

namespace glmbslam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Exhaustive search over every partial matching using only finite entries: the best is the one with the most
/// pairs, then the least cost.
struct Brute {
  int best_pairs = -1;
  double best_cost = kInf;
};

void enumerate(const Eigen::MatrixXd& c, int row, std::vector<char>& col_used, int pairs, double cost,
               Brute& b) {
  if (row == c.rows()) {
    if (pairs > b.best_pairs || (pairs == b.best_pairs && cost < b.best_cost)) {
      b.best_pairs = pairs;
      b.best_cost = cost;
    }
    return;
  }
  enumerate(c, row + 1, col_used, pairs, cost, b);  // row unassigned
  for (int j = 0; j < c.cols(); ++j) {
    if (col_used[j] || c(row, j) == kInf) continue;
    col_used[j] = 1;
    enumerate(c, row + 1, col_used, pairs + 1, cost + c(row, j), b);
    col_used[j] = 0;
  }
}

Brute brute_force(const Eigen::MatrixXd& c) {
  Brute b;
  std::vector<char> used(static_cast<size_t>(c.cols()), 0);
  enumerate(c, 0, used, 0, 0.0, b);
  return b;
}

/// Checks the structural validity of a result and returns (pairs, finite cost).
std::pair<int, double> check_valid(const Eigen::MatrixXd& c, const AssignmentResult& r) {
  EXPECT_EQ(r.row_to_col.size(), static_cast<size_t>(c.rows()));
  std::vector<char> used(static_cast<size_t>(c.cols()), 0);
  int pairs = 0;
  double cost = 0.0;
  for (int i = 0; i < c.rows(); ++i) {
    const int j = r.row_to_col[static_cast<size_t>(i)];
    if (j < 0) {
      EXPECT_EQ(j, -1);
      continue;
    }
    EXPECT_LT(j, c.cols());
    EXPECT_FALSE(used[static_cast<size_t>(j)]) << "column used twice";
    used[static_cast<size_t>(j)] = 1;
    EXPECT_NE(c(i, j), kInf) << "forbidden entry assigned";
    ++pairs;
    cost += c(i, j);
  }
  return {pairs, cost};
}

void run_random(std::uint64_t seed, double inf_probability, bool integer_costs) {
  RandomStream rng(seed);
  int infeasible_seen = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + static_cast<int>(rng.index(6));
    const int m = 1 + static_cast<int>(rng.index(6));
    Eigen::MatrixXd c(n, m);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) {
        // Integer costs produce many ties; real costs include negatives.
        c(i, j) = integer_costs ? static_cast<double>(rng.index(4)) : rng.uniform(-5.0, 10.0);
        if (rng.uniform() < inf_probability) c(i, j) = kInf;
      }
    }
    const Brute b = brute_force(c);
    const AssignmentResult r = solve_linear_assignment(c);
    const auto [pairs, cost] = check_valid(c, r);
    EXPECT_EQ(pairs, b.best_pairs) << "trial " << trial;
    EXPECT_NEAR(cost, b.best_cost, 1e-9) << "trial " << trial;
    const bool feasible = b.best_pairs == std::min(n, m);
    EXPECT_EQ(r.feasible, feasible) << "trial " << trial;
    if (feasible) {
      EXPECT_NEAR(r.cost, b.best_cost, 1e-9);
    } else {
      EXPECT_EQ(r.cost, kInf);
      ++infeasible_seen;
    }
  }
  if (inf_probability > 0.3) {
    EXPECT_GT(infeasible_seen, 0) << "the test should exercise infeasible problems";
  }
}

TEST(LinearAssignment, MatchesBruteForceFiniteReal) {
  run_random(1, 0.0, false);
}
TEST(LinearAssignment, MatchesBruteForceFiniteIntegerTies) {
  run_random(2, 0.0, true);
}
TEST(LinearAssignment, MatchesBruteForceSomeForbidden) {
  run_random(3, 0.2, false);
}
TEST(LinearAssignment, MatchesBruteForceManyForbidden) {
  run_random(4, 0.5, false);
}
TEST(LinearAssignment, MatchesBruteForceManyForbiddenTies) {
  run_random(5, 0.5, true);
}

TEST(LinearAssignment, HandComputedSquare) {
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3,  //
      2, 0, 5,   //
      3, 2, 2;
  const AssignmentResult r = solve_linear_assignment(c);
  EXPECT_TRUE(r.feasible);
  EXPECT_DOUBLE_EQ(r.cost, 5.0);  // 1 + 2 + 2
  EXPECT_EQ(r.row_to_col, (std::vector<int>{1, 0, 2}));
}

TEST(LinearAssignment, TallAndWide) {
  Eigen::MatrixXd tall(3, 2);
  tall << 1, 10,  //
      0, 10,      //
      10, 3;
  AssignmentResult r = solve_linear_assignment(tall);
  EXPECT_TRUE(r.feasible);
  EXPECT_DOUBLE_EQ(r.cost, 3.0);
  EXPECT_EQ(r.row_to_col, (std::vector<int>{-1, 0, 1}));
  r = solve_linear_assignment(Eigen::MatrixXd(tall.transpose()));
  EXPECT_DOUBLE_EQ(r.cost, 3.0);
  EXPECT_EQ(r.row_to_col, (std::vector<int>{1, 2}));
}

TEST(LinearAssignment, EmptyAndAllForbidden) {
  AssignmentResult r = solve_linear_assignment(Eigen::MatrixXd(0, 4));
  EXPECT_TRUE(r.feasible);
  EXPECT_TRUE(r.row_to_col.empty());
  r = solve_linear_assignment(Eigen::MatrixXd(3, 0));
  EXPECT_TRUE(r.feasible);
  EXPECT_EQ(r.row_to_col, (std::vector<int>{-1, -1, -1}));
  const Eigen::MatrixXd all_inf = Eigen::MatrixXd::Constant(2, 3, kInf);
  r = solve_linear_assignment(all_inf);
  EXPECT_FALSE(r.feasible);
  EXPECT_EQ(r.cost, kInf);
  EXPECT_EQ(r.row_to_col, (std::vector<int>{-1, -1}));
}

TEST(LinearAssignment, RejectsNan) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(2, 2);
  c(1, 0) = std::nan("");
  EXPECT_THROW(solve_linear_assignment(c), std::invalid_argument);
}

TEST(LinearAssignment, LargerRandomAgreesWithOptimalityCertificate) {
  // For a 60×80 problem no brute force is possible; check instead that no 2-swap or move to a free column
  // improves the solution (a necessary condition for optimality), and that the cost is finite.
  RandomStream rng(11);
  Eigen::MatrixXd c(60, 80);
  for (int i = 0; i < c.rows(); ++i)
    for (int j = 0; j < c.cols(); ++j) c(i, j) = rng.uniform(0.0, 100.0);
  const AssignmentResult r = solve_linear_assignment(c);
  ASSERT_TRUE(r.feasible);
  std::vector<int> col_owner(80, -1);
  for (int i = 0; i < 60; ++i) col_owner[static_cast<size_t>(r.row_to_col[static_cast<size_t>(i)])] = i;
  for (int i = 0; i < 60; ++i) {
    const int ji = r.row_to_col[static_cast<size_t>(i)];
    for (int j = 0; j < 80; ++j) {
      const int k = col_owner[static_cast<size_t>(j)];
      if (k < 0) {
        EXPECT_LE(c(i, ji), c(i, j) + 1e-9);
      } else if (k != i) {
        const int jk = r.row_to_col[static_cast<size_t>(k)];
        EXPECT_LE(c(i, ji) + c(k, jk), c(i, jk) + c(k, ji) + 1e-9);
      }
    }
  }
}

}  // namespace
}  // namespace glmbslam

namespace glmbslam {
namespace {

TEST(LinearAssignment, ReusableSolverMatchesFreshSolves) {
  // One solver across problems of changing shape (buffers shrink and grow) gives the same answers.
  RandomStream rng(12);
  LinearAssignmentSolver solver;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng.index(9));
    const int m = 1 + static_cast<int>(rng.index(9));
    Eigen::MatrixXd c(n, m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) c(i, j) = rng.uniform() < 0.3 ? kInf : rng.uniform(-1.0, 1.0);
    const AssignmentResult fresh = solve_linear_assignment(c);
    const AssignmentResult& reused = solver.solve(c);
    EXPECT_EQ(reused.feasible, fresh.feasible);
    EXPECT_EQ(reused.cost, fresh.cost);
    EXPECT_EQ(reused.row_to_col, fresh.row_to_col);
    const Brute b = brute_force(c);
    EXPECT_NEAR(check_valid(c, reused).second, b.best_cost, 1e-9);
  }
}

}  // namespace
}  // namespace glmbslam
