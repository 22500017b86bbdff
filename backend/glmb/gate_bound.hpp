#pragma once
// A cheap necessary condition of the χ² gate νᵀS⁻¹ν ≤ gate, shared by the map updates (Innovation::update)
// and the optimal proposal's association rows: for an SPD S, νᵀS⁻¹ν ≥ ν_i² / S_ii (Cauchy–Schwarz), so a
// residual with some ν_i² > gate · S_ii fails the gate without the triangular solve. The bound is widened by
// 1e-6 so that it never rejects a pair the exact test, with its rounding, would accept.
#include <Eigen/Core>

namespace glmbslam::backend {

/// True when ν certainly fails the gate: some ν_i² exceeds gate · S_ii (widened by 1e-6). `diag_S` is
/// diag(S).
template <class Vec>
bool fails_gate_on_diagonal(const Vec& nu, const Vec& diag_S, double gate) {
  return (nu.array().square() > (gate * (1.0 + 1e-6)) * diag_S.array()).any();
}

}  // namespace glmbslam::backend
