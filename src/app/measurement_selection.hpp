#pragma once
// Choosing the stereo measurements handed to the backend: those inside the model's depth range and detected
// at a pyramid level the model's noise describes, spread over the image by a grid (round-robin over the
// cells, strongest response first), at most `max_count`. Spreading matters: a pose is best constrained by
// landmarks all over the image, and the backend's cost grows with the number of measurements.
#include <string>
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

/// Per measurement of this frame: the VO tracked it from a measurement of the previous frame flagged in
/// `previous_flags` (`previous_measurement[i]`: index in the previous frame of measurement i's match, −1 =
/// none; as frontend::VoEstimate::previous_measurement).
std::vector<char> tracked_from(const std::vector<int>& previous_measurement,
                               const std::vector<char>& previous_flags);

/// Which of this frame's measurements the backend's control u_k, Q_k leaves out
/// (`pipeline.control_excludes`):
///  - "selected" (the default): every measurement handed to the backend in this frame, so no pixel is counted
///    twice (once in the VO motion, once in a landmark update); a feature handed over for the first time then
///    loses its previous-to-current pixel pair, since its landmark is born now and says nothing about the
///    motion (on rendered KITTI 01, 300 instead of 150 measurements per frame raised the drift from 0.72 to
///    0.85 %).
///  - "tracked": only those handed over in this frame and in the previous one (`tracked_selected`), whose
///    landmark already holds the previous pixel; the new feature's pair stays in the control, at the price of
///    its current pixel entering both the control and its landmark's initial position. Measured against
///    "selected" it is mixed (docs/investigations.md, "Which points the control leaves out").
///  - "none": the control is the full VO motion.
/// `selected` and `tracked_selected` are index-aligned with the frame's measurements.
std::vector<char> control_exclusion(const std::string& mode, const std::vector<char>& selected,
                                    const std::vector<char>& tracked_selected);

}  // namespace glmbslam::app
