#pragma once
// Particle trajectories as parent-linked immutable nodes: particles that share a history share its nodes,
// so resampling copies one pointer per particle.
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::backend {

template <class State>
struct TrajectoryNode {
  State pose;      ///< the particle's pose sample x_k (the map is conditioned on it)
  State estimate;  ///< Rao–Blackwellised point estimate of x_k: the proposal mean (optimal kernel) or x_k
  int step = 0;
  std::shared_ptr<const TrajectoryNode> parent;

  TrajectoryNode(const State& p, int k, std::shared_ptr<const TrajectoryNode> par)
      : pose(p), estimate(p), step(k), parent(std::move(par)) {}
  TrajectoryNode(const State& p, const State& e, int k, std::shared_ptr<const TrajectoryNode> par)
      : pose(p), estimate(e), step(k), parent(std::move(par)) {}
  TrajectoryNode(const TrajectoryNode&) = delete;
  TrajectoryNode& operator=(const TrajectoryNode&) = delete;
  /// Unlinks a long uniquely-owned chain iteratively (no deep recursion on destruction).
  ~TrajectoryNode() {
    std::shared_ptr<const TrajectoryNode> p = std::move(parent);
    while (p && p.use_count() == 1) {
      std::shared_ptr<const TrajectoryNode> next = std::move(const_cast<TrajectoryNode&>(*p).parent);
      p = std::move(next);
    }
  }

  /// Poses from step 0 to this node's step.
  std::vector<State, Eigen::aligned_allocator<State>> poses() const {
    std::vector<State, Eigen::aligned_allocator<State>> out;
    for (const TrajectoryNode* n = this; n != nullptr; n = n->parent.get()) out.push_back(n->pose);
    return {out.rbegin(), out.rend()};
  }

  /// Point estimates (see `estimate`) from step 0 to this node's step.
  std::vector<State, Eigen::aligned_allocator<State>> estimates() const {
    std::vector<State, Eigen::aligned_allocator<State>> out;
    for (const TrajectoryNode* n = this; n != nullptr; n = n->parent.get()) out.push_back(n->estimate);
    return {out.rbegin(), out.rend()};
  }
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace glmbslam::backend
