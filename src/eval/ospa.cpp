#include "eval/ospa.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/linear_assignment.hpp"

namespace glmbslam::eval {
namespace {

void check(const PointSet& x, const PointSet& y, double c, double p) {
  if (!(c > 0.0) || !std::isfinite(c))
    throw std::invalid_argument("OSPA/GOSPA: cut-off c must be finite and > 0");
  if (!(p >= 1.0) || !std::isfinite(p))
    throw std::invalid_argument("OSPA/GOSPA: order p must be finite and ≥ 1");
  if (x.cols() > 0 && y.cols() > 0 && x.rows() != y.rows()) {
    throw std::invalid_argument("OSPA/GOSPA: point sets have different dimensions");
  }
}

/// Cost matrix min(‖x_i − y_j‖, c)^p, rows = points of x, columns = points of y.
Eigen::MatrixXd cut_off_costs(const PointSet& x, const PointSet& y, double c, double p) {
  Eigen::MatrixXd cost(x.cols(), y.cols());
  const double cp = std::pow(c, p);
  for (Eigen::Index j = 0; j < y.cols(); ++j) {
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const double d = (x.col(i) - y.col(j)).norm();
      cost(i, j) = d >= c ? cp : std::pow(d, p);
    }
  }
  return cost;
}

}  // namespace

PointSet point_set_from(const std::vector<Eigen::VectorXd>& points) {
  if (points.empty()) return PointSet(0, 0);
  const Eigen::Index d = points.front().size();
  PointSet s(d, static_cast<Eigen::Index>(points.size()));
  for (size_t k = 0; k < points.size(); ++k) {
    if (points[k].size() != d) throw std::invalid_argument("point_set_from: points of different dimensions");
    s.col(static_cast<Eigen::Index>(k)) = points[k];
  }
  return s;
}

OspaResult ospa(const PointSet& x, const PointSet& y, double c, double p) {
  check(x, y, c, p);
  OspaResult r;
  const Eigen::Index m = std::min(x.cols(), y.cols());
  const Eigen::Index n = std::max(x.cols(), y.cols());
  if (n == 0) return r;
  const double cp = std::pow(c, p);
  double loc = 0.0;
  if (m > 0) {
    const Eigen::MatrixXd cost = cut_off_costs(x, y, c, p);
    loc = solve_linear_assignment(cost).cost;  // always feasible: every entry is finite
  }
  const double card = cp * static_cast<double>(n - m);
  const double inv_n = 1.0 / static_cast<double>(n);
  r.distance = std::pow(inv_n * (loc + card), 1.0 / p);
  r.localisation = std::pow(inv_n * loc, 1.0 / p);
  r.cardinality = std::pow(inv_n * card, 1.0 / p);
  return r;
}

GospaResult gospa(const PointSet& x, const PointSet& y, double c, double p) {
  check(x, y, c, p);
  GospaResult r;
  const double half_cp = 0.5 * std::pow(c, p);
  const Eigen::Index nx = x.cols();
  const Eigen::Index ny = y.cols();
  if (nx > 0 && ny > 0) {
    // With α = 2, assigning a pair costs min(d, c)^p: a pair at d ≥ c costs c^p, the same as one missed plus
    // one false, so it is counted as unassigned. min(|X|,|Y|) pairs are then assigned optimally.
    const Eigen::MatrixXd cost = cut_off_costs(x, y, c, p);
    const AssignmentResult a = solve_linear_assignment(cost);
    for (Eigen::Index i = 0; i < nx; ++i) {
      const int j = a.row_to_col[static_cast<size_t>(i)];
      if (j < 0) continue;
      if ((x.col(i) - y.col(j)).norm() < c) {
        r.localisation += cost(i, j);
        ++r.assigned_count;
      }
    }
  }
  r.missed_count = static_cast<int>(nx) - r.assigned_count;
  r.false_count = static_cast<int>(ny) - r.assigned_count;
  r.missed = half_cp * r.missed_count;
  r.false_ = half_cp * r.false_count;
  r.distance = std::pow(r.localisation + r.missed + r.false_, 1.0 / p);
  return r;
}

}  // namespace glmbslam::eval
