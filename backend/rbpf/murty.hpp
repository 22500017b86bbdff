#pragma once
// Murty's k-best assignments (Murty 1968, with the partitioning of Miller–Stone–Cox) on top of
// glmbslam::solve_linear_assignment, and the ranked landmark-to-measurement associations of paper 003
// (digest 2.4).
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::backend {

/// One complete assignment: row_to_col[i] is the column of row i; cost = Σ_i cost(i, row_to_col[i]).
struct RankedAssignment {
  std::vector<int> row_to_col;
  double cost = 0.0;
};

struct MurtyOptions {
  std::size_t max_solutions = 50;  ///< Γ̄: stop after this many assignments
  /// Stop when an assignment costs more than best + max_cost_gap (that assignment is discarded). For a −log
  /// cost this is "less than e^{−gap} as likely as the best"; paper 003: gap = −log(1e-3). +∞ = no ratio
  /// stop.
  double max_cost_gap = std::numeric_limits<double>::infinity();
};

/// The assignments of an n×m cost matrix (n ≤ m, every row assigned to a distinct column, +∞ = forbidden) in
/// increasing order of cost, at most options.max_solutions of them. Returns an empty list when no complete
/// assignment avoids the forbidden entries (or when max_solutions is 0); a 0×m matrix has one empty
/// assignment. Throws std::invalid_argument if n > m or an entry is NaN or −∞.
std::vector<RankedAssignment> murty_k_best(const Eigen::MatrixXd& cost, const MurtyOptions& options = {});

/// A data-association hypothesis for M landmarks and J measurements: measurement_of[i] = j (0-based) when
/// landmark i is detected by z_j, −1 when it is missed; log_weight = log γ = Σ_i log ℓ^{i, φ(i)} (Eq. 32).
struct AssociationHypothesis {
  std::vector<int> measurement_of;
  double log_weight = 0.0;
};

/// Paper 003 Eq. 28–32: ranked associations from the log-likelihood table log_detect (M×J, log ℓ^{i,j},
/// −∞ = gated out) and log_miss (M, log ℓ^{i,0} = log(1 − p_D), −∞ allowed for p_D = 1). The cost matrix is
/// L = −log[ℓ^{i,j} | diag(ℓ^{i,0})] (M × (J + M)), off-diagonal misdetection entries +∞. Hypotheses are
/// returned best first. If no hypothesis exists (every landmark needs a detection and none is possible) the
/// list is empty.
std::vector<AssociationHypothesis> rank_associations(const Eigen::MatrixXd& log_detect,
                                                     const Eigen::VectorXd& log_miss,
                                                     const MurtyOptions& options = {});

}  // namespace glmbslam::backend
