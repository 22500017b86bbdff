#include "backend/rbpf/murty.hpp"

#include <cmath>
#include <memory>
#include <queue>
#include <stdexcept>

#include "core/linear_assignment.hpp"

namespace glmbslam::backend {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A subproblem of Murty's partition: the cost matrix with its forced and forbidden entries applied, and its
/// best assignment.
struct Node {
  Eigen::MatrixXd cost;  // forbidden entries = +∞; a forced pair (i, j) leaves only (i, j) finite in row i
  std::vector<int> forced;  // forced[i] = column forced for row i, −1 if free
  RankedAssignment solution;
};

struct NodeOrder {
  bool operator()(const Node* a, const Node* b) const { return a->solution.cost > b->solution.cost; }
};

/// Solves a node's matrix with `solver` (one per ranking: its buffers are reused); false if infeasible.
bool solve(Node& node, LinearAssignmentSolver& solver) {
  const AssignmentResult& r = solver.solve(node.cost);
  if (!r.feasible || !std::isfinite(r.cost)) return false;
  for (int c : r.row_to_col) {
    if (c < 0) return false;
  }
  node.solution.row_to_col = r.row_to_col;
  node.solution.cost = r.cost;
  return true;
}

}  // namespace

std::vector<RankedAssignment> murty_k_best(const Eigen::MatrixXd& cost, const MurtyOptions& options) {
  const Eigen::Index n = cost.rows(), m = cost.cols();
  if (n > m) throw std::invalid_argument("murty_k_best: more rows than columns");
  for (Eigen::Index i = 0; i < cost.size(); ++i) {
    const double c = cost.data()[i];
    if (std::isnan(c) || c == -kInf) throw std::invalid_argument("murty_k_best: NaN or -inf cost");
  }
  std::vector<RankedAssignment> out;
  if (options.max_solutions == 0) return out;
  if (n == 0) {
    out.push_back(RankedAssignment{});
    return out;
  }

  LinearAssignmentSolver solver;
  std::vector<std::unique_ptr<Node>> storage;
  std::priority_queue<Node*, std::vector<Node*>, NodeOrder> queue;
  auto root = std::make_unique<Node>();
  root->cost = cost;
  root->forced.assign(static_cast<std::size_t>(n), -1);
  if (!solve(*root, solver)) return out;
  queue.push(root.get());
  storage.push_back(std::move(root));

  double best = kInf;
  while (!queue.empty() && out.size() < options.max_solutions) {
    Node* node = queue.top();
    queue.pop();
    if (out.empty()) best = node->solution.cost;
    if (node->solution.cost - best > options.max_cost_gap) break;
    out.push_back(node->solution);
    if (out.size() == options.max_solutions) break;

    // Partition the node's space around its solution: child t forces the solution's pairs of the free rows
    // before t and forbids the pair of free row t.
    Eigen::MatrixXd partial = node->cost;
    std::vector<int> forced = node->forced;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (forced[static_cast<std::size_t>(i)] >= 0) continue;
      const int j = node->solution.row_to_col[static_cast<std::size_t>(i)];
      auto child = std::make_unique<Node>();
      child->cost = partial;
      child->cost(i, j) = kInf;
      child->forced = forced;
      if (solve(*child, solver)) {
        queue.push(child.get());
        storage.push_back(std::move(child));
      }
      // Force (i, j) for the following children: row i keeps only column j, column j only row i.
      const double keep = partial(i, j);
      partial.row(i).setConstant(kInf);
      partial.col(j).setConstant(kInf);
      partial(i, j) = keep;
      forced[static_cast<std::size_t>(i)] = j;
    }
  }
  return out;
}

std::vector<AssociationHypothesis> rank_associations(const Eigen::MatrixXd& log_detect,
                                                     const Eigen::VectorXd& log_miss,
                                                     const MurtyOptions& options) {
  const Eigen::Index M = log_detect.rows(), J = log_detect.cols();
  if (log_miss.size() != M) throw std::invalid_argument("rank_associations: log_miss size differs from rows");
  Eigen::MatrixXd cost = Eigen::MatrixXd::Constant(M, J + M, kInf);
  for (Eigen::Index i = 0; i < M; ++i) {
    for (Eigen::Index j = 0; j < J; ++j) {
      const double l = log_detect(i, j);
      if (std::isnan(l) || l == kInf)
        throw std::invalid_argument("rank_associations: NaN or +inf log-likelihood");
      cost(i, j) = -l;  // −(−∞) = +∞: gated out
    }
    if (std::isnan(log_miss(i)) || log_miss(i) == kInf) {
      throw std::invalid_argument("rank_associations: NaN or +inf misdetection log-likelihood");
    }
    cost(i, J + i) = -log_miss(i);
  }
  const std::vector<RankedAssignment> ranked = murty_k_best(cost, options);
  std::vector<AssociationHypothesis> out(ranked.size());
  for (std::size_t t = 0; t < ranked.size(); ++t) {
    out[t].log_weight = -ranked[t].cost;
    out[t].measurement_of.resize(static_cast<std::size_t>(M));
    for (Eigen::Index i = 0; i < M; ++i) {
      const int c = ranked[t].row_to_col[static_cast<std::size_t>(i)];
      out[t].measurement_of[static_cast<std::size_t>(i)] = c < J ? c : -1;
    }
  }
  return out;
}

}  // namespace glmbslam::backend
