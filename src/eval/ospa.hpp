#pragma once
// Set-distance metrics for point sets in ℝ^d (maps of landmarks, multi-target states), each computed with an
// optimal assignment (core/linear_assignment).
// OSPA: Schuhmacher, Vo, Vo, "A consistent metric for performance evaluation of multi-object filters", IEEE
// TSP 2008. GOSPA: Rahmathullah, García-Fernández, Svensson, "Generalized optimal sub-pattern assignment
// metric", FUSION 2017.
#include <vector>

#include <Eigen/Core>

namespace glmbslam::eval {

/// A point set as the columns of a d×N matrix (N may be 0). Both sets must have the same d when non-empty.
using PointSet = Eigen::MatrixXd;

/// Builds a d×N point set from a list of vectors (all of size d); an empty list gives a 0×0 set.
PointSet point_set_from(const std::vector<Eigen::VectorXd>& points);

/// OSPA distance with cut-off c > 0 and order p ≥ 1 (Schuhmacher et al. eq. (3)), for |X| = m ≤ |Y| = n:
/// ( (1/n) ( min_π Σ_i min(c, ‖x_i − y_π(i)‖)^p + c^p (n − m) ) )^(1/p); 0 if both sets are empty, c if
/// exactly one is empty. Symmetric in X and Y.
struct OspaResult {
  double distance = 0.0;
  double localisation = 0.0;  ///< localisation component ((1/n) Σ d_c^p)^(1/p)
  double cardinality = 0.0;   ///< cardinality component ((1/n) c^p (n − m))^(1/p)
};
OspaResult ospa(const PointSet& x, const PointSet& y, double c, double p);

/// GOSPA with cut-off c > 0, order p ≥ 1 and α = 2 (Rahmathullah et al. Proposition 1):
/// d = ( min_γ Σ_{(i,j)∈γ} ‖x_i − y_j‖^p + (c^p/2)(|X| − |γ|) + (c^p/2)(|Y| − |γ|) )^(1/p),
/// over partial assignments γ; pairs at distance ≥ c are never better than leaving both unassigned.
/// X is the ground truth and Y the estimate: unassigned x are "missed", unassigned y are "false".
struct GospaResult {
  double distance = 0.0;      ///< d above
  double localisation = 0.0;  ///< Σ over assigned pairs of ‖x − y‖^p (p-th power units)
  double missed = 0.0;        ///< (c^p/2)·missed_count (p-th power units)
  double false_ = 0.0;  ///< (c^p/2)·false_count (p-th power units); distance^p = localisation+missed+false_
  int assigned_count = 0;
  int missed_count = 0;
  int false_count = 0;
};
GospaResult gospa(const PointSet& x, const PointSet& y, double c, double p);

}  // namespace glmbslam::eval
