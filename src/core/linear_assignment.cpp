// Shortest-augmenting-path Hungarian method with row/column potentials (Kuhn–Munkres in the Jonker–Volgenant
// formulation): rows are inserted one at a time, each by a Dijkstra-like search over reduced costs
// a(i,j) - u(i) - v(j) ≥ 0, so the whole solve is O(n² m) for n ≤ m.
#include "core/linear_assignment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace glmbslam {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

/// Solves the n×m problem held in work_ (n ≤ m, all entries finite); fills col_of_row_ (0-based, all
/// assigned).
void LinearAssignmentSolver::solve_square_or_wide() {
  const RowMajorMatrix& a = work_;
  const int n = static_cast<int>(a.rows());
  const int m = static_cast<int>(a.cols());
  // 1-based arrays; column 0 is the virtual start column of each augmentation.
  u_.assign(static_cast<size_t>(n) + 1, 0.0);
  v_.assign(static_cast<size_t>(m) + 1, 0.0);
  minv_.resize(static_cast<size_t>(m) + 1);
  p_.assign(static_cast<size_t>(m) + 1, 0);  // p[j] = row (1-based) matched to column j, 0 = free
  way_.assign(static_cast<size_t>(m) + 1, 0);
  used_.resize(static_cast<size_t>(m) + 1);
  std::vector<double>& u = u_;
  std::vector<double>& v = v_;
  std::vector<double>& minv = minv_;
  std::vector<int>& p = p_;
  std::vector<int>& way = way_;
  std::vector<char>& used = used_;
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), kInf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      const double* row = a.data() + static_cast<std::ptrdiff_t>(i0 - 1) * m;
      const double ui0 = u[i0];
      double delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = row[j - 1] - ui0 - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      if (j1 == 0) {
        // Only possible with non-finite reduced costs (overflow); the caller guarantees finite input.
        throw std::runtime_error("solve_linear_assignment: numerical breakdown (non-finite reduced costs)");
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {  // augment along the alternating path back to the virtual column
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  col_of_row_.assign(static_cast<size_t>(n), -1);
  for (int j = 1; j <= m; ++j) {
    if (p[j] != 0) col_of_row_[static_cast<size_t>(p[j] - 1)] = j - 1;
  }
}

AssignmentResult solve_linear_assignment(const Eigen::MatrixXd& cost) {
  LinearAssignmentSolver solver;
  return solver.solve(cost);
}

const AssignmentResult& LinearAssignmentSolver::solve(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows());
  const int cols = static_cast<int>(cost.cols());
  AssignmentResult& result = result_;
  result.row_to_col.assign(static_cast<size_t>(rows), -1);
  result.cost = 0.0;
  result.feasible = true;
  if (rows == 0 || cols == 0) return result;

  // Validate and find the range of the finite entries.
  bool any_forbidden = false;
  double lo = kInf;
  double hi = -kInf;
  for (int c = 0; c < cols; ++c) {
    for (int r = 0; r < rows; ++r) {
      const double x = cost(r, c);
      if (std::isnan(x) || x == -kInf) {
        throw std::invalid_argument("solve_linear_assignment: cost matrix holds NaN or -infinity");
      }
      if (x == kInf) {
        any_forbidden = true;
      } else {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
  }

  // Work on an n×m problem with n ≤ m (transpose if needed), row-major for contiguous row scans.
  const bool transposed = rows > cols;
  const int n = transposed ? cols : rows;
  const int m = transposed ? rows : cols;
  RowMajorMatrix& a = work_;
  a.resize(n, m);
  if (transposed) {
    a = cost.transpose();
  } else {
    a = cost;
  }
  if (any_forbidden) {
    // Forbidden entries get a penalty M larger than the spread of any finite assignment: after shifting
    // finite entries to [0, R], an assignment using f forbidden entries costs in [f·M, f·M + (n − f)·R], so
    // with M > n·R the optimum first minimises f (= maximises the finite matching) and then the finite cost.
    const double range = (lo == kInf) ? 0.0 : hi - lo;
    const double shift = (lo == kInf) ? 0.0 : lo;
    const double penalty = (static_cast<double>(n) + 1.0) * (range + 1.0);
    for (Eigen::Index k = 0; k < a.size(); ++k) {
      double& x = a.data()[k];
      x = (x == kInf) ? penalty : x - shift;
    }
  }

  solve_square_or_wide();
  const std::vector<int>& col_of_row = col_of_row_;

  double total = 0.0;
  for (int i = 0; i < n; ++i) {
    const int j = col_of_row[static_cast<size_t>(i)];
    const int r = transposed ? j : i;
    const int c = transposed ? i : j;
    const double x = cost(r, c);
    if (x == kInf) {
      result.feasible = false;  // leave this pair unassigned
      continue;
    }
    result.row_to_col[static_cast<size_t>(r)] = c;
    total += x;
  }
  result.cost = result.feasible ? total : kInf;
  return result;
}

}  // namespace glmbslam
