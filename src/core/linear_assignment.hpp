#pragma once
// Rectangular linear assignment (minimum-cost bipartite matching) by the shortest-augmenting-path Hungarian
// method with potentials (Jonker–Volgenant style augmentation), O(min(n,m)² · max(n,m)).
#include <vector>

#include <Eigen/Core>

namespace glmbslam {

/// Result of solve_linear_assignment.
struct AssignmentResult {
  /// row_to_col[i] = column assigned to row i, or -1 if row i is unassigned (only when rows > columns,
  /// or when the problem is infeasible, see below).
  std::vector<int> row_to_col;
  /// Total cost of the assigned pairs (sum of cost(i, row_to_col[i]) over assigned rows). +infinity if
  /// infeasible.
  double cost = 0.0;
  /// False if no assignment of min(n, m) pairs avoids every forbidden (+infinity) entry.
  bool feasible = true;
};

/// Minimises the total cost over assignments of min(n, m) pairs of an n×m cost matrix: each row gets at most
/// one column, each column at most one row. Entries equal to +infinity are forbidden. Finite entries may be
/// negative. NaN or -infinity entries are treated as errors (std::invalid_argument).
///
/// Infeasible case: if no assignment of min(n, m) pairs avoids the forbidden entries, the result has
/// feasible = false, cost = +infinity, and row_to_col holds a maximum-cardinality assignment using only
/// finite entries that has minimum cost among assignments of that cardinality (the rows that could not be
/// matched are -1). An empty matrix (n = 0 or m = 0) gives an empty/all -1 assignment with cost 0 and
/// feasible = true.
AssignmentResult solve_linear_assignment(const Eigen::MatrixXd& cost);

/// The same solver keeping its work buffers between calls (no allocation once they have grown), for hot
/// loops. Not thread-safe: use one instance per thread.
class LinearAssignmentSolver {
 public:
  /// As solve_linear_assignment; the result stays valid until the next call.
  const AssignmentResult& solve(const Eigen::MatrixXd& cost);

 private:
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  void solve_square_or_wide();
  RowMajorMatrix work_;
  std::vector<double> u_, v_, minv_;
  std::vector<int> p_, way_, col_of_row_;
  std::vector<char> used_;
  AssignmentResult result_;
};

}  // namespace glmbslam
