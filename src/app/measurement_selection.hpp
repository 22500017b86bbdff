#pragma once
// Choosing the stereo measurements handed to the backend: those inside the model's depth range and detected
// at a pyramid level the model's noise describes, spread over the image by a grid (round-robin over the
// cells, strongest response first), at most `max_count`. Spreading matters: a pose is best constrained by
// landmarks all over the image, and the backend's cost grows with the number of measurements.
#include <vector>

#include "frontend/stereo_measurement.hpp"

namespace glmbslam::app {

struct SelectionGrid {
  int columns = 10;
  int rows = 4;
  double width = 1241.0;
  double height = 376.0;
};

/// Which measurements may be handed to the backend.
struct SelectionRules {
  double min_depth = 1.0;   ///< nearest depth (m), the model's field of view
  double max_depth = 20.0;  ///< farthest depth (m), the model's field of view
  /// Highest pyramid level: the backend's stereo model has one pixel σ, that of level-0 keypoints, while a
  /// keypoint of level L is located to σ · scale_factor^L; the coarser ones would be over-weighted.
  int max_octave = 0;
  int max_count = 150;  ///< at most this many
};

/// Indices into `measurements` of the selected ones, in a deterministic order. Within each cell the
/// measurements flagged in `preferred` (index-aligned with `measurements`; empty = none) come first: the
/// pipeline flags those the VO tracked from a measurement it handed to the backend in the previous frame, so
/// the backend keeps re-observing its landmarks instead of seeing a new subset of the features every frame.
std::vector<int> select_measurements(const frontend::StereoMeasurementList& measurements,
                                     const SelectionGrid& grid, const SelectionRules& rules,
                                     const std::vector<char>& preferred = {});

}  // namespace glmbslam::app
