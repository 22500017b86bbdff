#pragma once
// Pairing an estimated trajectory with its ground truth: KITTI files pair line by line (same count required);
// TUM files pair by timestamp (nearest ground-truth stamp within a tolerance, one-to-one, in time order).
#include <string>

#include "core/types.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::eval {

/// Ground truth and estimate, pose i of one matching pose i of the other.
struct AssociatedTrajectories {
  PoseList gt;
  PoseList est;
  std::vector<double> timestamps;  ///< ground-truth stamps of the pairs (empty for KITTI)
  int unmatched_est = 0;           ///< estimated poses without a ground-truth stamp within the tolerance
};

/// KITTI: requires the same number of poses; throws InputError naming `est_path` otherwise.
AssociatedTrajectories associate_by_index(const PoseList& gt, const PoseList& est,
                                          const std::string& est_path);

/// TUM: for each estimated stamp (increasing), the nearest unused ground-truth stamp within `tolerance_s`
/// (greedy in time order). Throws InputError naming `est_path` when fewer than 2 pairs are found.
AssociatedTrajectories associate_by_timestamp(const io::Trajectory& gt, const io::Trajectory& est,
                                              double tolerance_s, const std::string& est_path);

}  // namespace glmbslam::eval
