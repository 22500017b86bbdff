#pragma once
// The measurement-set check of the map updates (δ-GLMB, LMB): a non-finite measurement is an InputError
// naming the time step and the measurement, raised before the update changes anything.
#include <cstddef>
#include <string>

#include "core/error.hpp"

namespace glmbslam::backend {

/// Throws InputError if a measurement of Z is not finite (Meas::is_finite).
template <class Meas, class MeasurementSet>
void validate_measurement_set(const Meas& model, const MeasurementSet& Z, int step) {
  for (std::size_t j = 0; j < Z.size(); ++j) {
    if (!model.is_finite(Z[j]))
      throw InputError("measurement set", "time step " + std::to_string(step) + ": measurement " +
                                              std::to_string(j) + " is not finite");
  }
}

}  // namespace glmbslam::backend
