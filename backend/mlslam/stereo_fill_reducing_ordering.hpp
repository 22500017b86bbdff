#pragma once
// A fill-reducing elimination order for the stereo M-step's normal equations by nested dissection (METIS,
// through CHOLMOD's Partition module). Ceres 2.1 orders sparse normal Cholesky by approximate minimum degree
// only; on a long stereo run whose landmarks are seen again on revisits (loop closures: on rendered KITTI 00,
// 1 % of the landmarks span ≥ 1000 frames) the pose system fills in and its factorisation dominates the
// M-step. The order is handed to Ceres as one elimination group per parameter block.
#include <vector>

namespace glmbslam::backend {

/// The nodes of the undirected graph `adjacency` (node b's neighbours, no self loops needed) in a nested
/// dissection elimination order (every node once). Throws std::runtime_error if CHOLMOD fails.
std::vector<int> nested_dissection_order(const std::vector<std::vector<int>>& adjacency);

}  // namespace glmbslam::backend
