#pragma once
// Choosing the stereo measurements handed to the backend: those inside the model's depth range, spread over
// the image by a grid (round-robin over the cells, strongest response first), at most `max_count`.
// Spreading matters: a pose is best constrained by landmarks all over the image, and the backend's cost grows
// with the number of measurements.
#include <vector>

#include "frontend/stereo_measurement.hpp"

namespace glmbslam::app {

struct SelectionGrid {
  int columns = 10;
  int rows = 4;
  double width = 1241.0;
  double height = 376.0;
};

/// Indices into `measurements` of the selected ones, in a deterministic order.
std::vector<int> select_measurements(const frontend::StereoMeasurementList& measurements,
                                     const SelectionGrid& grid, double min_depth, double max_depth,
                                     int max_count);

}  // namespace glmbslam::app
