#pragma once
// Evaluation of a trajectory whose ground truth covers only some frames (a partial download, a ground-truth
// system that lost track): the frames without ground truth are left out. ATE and RPE use the frames that have
// it; the KITTI segment metric runs on each stretch of consecutive frames with ground truth, its segments
// pooled into one result (a segment never bridges a gap).
#include <vector>

#include "eval/report.hpp"

namespace glmbslam::eval {

/// Maximal runs [first, last) of frames with mask[i] != 0.
std::vector<std::pair<std::size_t, std::size_t>> ground_truth_stretches(const std::vector<char>& mask);

/// Like evaluate_trajectory over the frames with mask[i] != 0 (an empty mask: every frame). `frames` of the
/// result counts the evaluated frames. std::invalid_argument if the sizes differ or no frame has ground
/// truth.
TrajectoryEvaluation evaluate_trajectory_masked(const PoseList& gt, const PoseList& est,
                                                const std::vector<char>& mask,
                                                const EvaluationOptions& options = EvaluationOptions());

}  // namespace glmbslam::eval
