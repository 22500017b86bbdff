#pragma once
// Paper 004's small 2D batch problem (Inostroza & Adams, RFS ML-SLAM; digest 3.4): 5 landmarks, 30 steps in 5
// segments of constant motion inside x ∈ [−3, 1] m, y ∈ [−1.5, 1.5] m, a 360° range-bearing sensor over
// 0.5–2.5 m, p_D 0.9, σ_r² = σ_b² = 1e-4, odometry variance 2e-4 (here on the unicycle control (v, ω), dt 1
// s, so 2e-4 m² and 2e-4 rad² per step as in the paper), clutter intensity 0.001 in (r, b) space (λ_c ≈
// 0.0126 per scan) unless a clutter rate is given. The paper draws neither the path nor the layout; this
// reconstruction [IMPL] drives left turns of 0.3 rad per step between straights at 0.15 m/s and places the
// landmarks along the path at 0.7–1.2 m. Each data seed is one Monte Carlo realisation.
#include <cstdint>

#include "sim/scenario2d.hpp"

namespace glmbslam::sim {

struct Paper004Options {
  double clutter_rate = -1.0;   ///< λ_c per scan; < 0 = the paper's intensity 0.001 over the sensor volume
  std::uint64_t data_seed = 0;  ///< the data realisation
};

/// Builds the scenario (deterministic for given options).
Scenario2D make_paper004_scenario(const Paper004Options& options = {});

}  // namespace glmbslam::sim
