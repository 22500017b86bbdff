#pragma once
// ground_truth.txt: the reference poses a stereo run's metrics were computed against (KITTI format, relative
// to the first processed frame, one pose per frame like trajectory.txt), so that other tools — the KITTI
// devkit, evo, `glmbslam eval --gt ground_truth.txt --est trajectory.txt` — reproduce metrics.json. For KITTI
// raw drives (OXTS) and EuRoC (body poses moved into the rectified left camera) this is the only place the
// converted reference exists.
#include <filesystem>
#include <vector>

#include "core/types.hpp"

namespace glmbslam::app {

/// Writes DIR/ground_truth.txt when there is ground truth (not null) and every frame has a measured pose
/// (mask empty or all set) and returns true. Otherwise nothing is written and a ground_truth.txt of an
/// earlier run in DIR is removed: without ground truth there is nothing to write, and with partial ground
/// truth the frames without a measurement hold placeholders (an info line says how many frames metrics.json
/// evaluated). Throws InputError naming the file on a write failure.
bool write_ground_truth_file(const std::filesystem::path& dir, const PoseList* ground_truth,
                             const std::vector<char>& mask);

}  // namespace glmbslam::app
