#pragma once
// Paper 004's 1D batch problem (Inostroza & Adams, RFS ML-SLAM, Sec. VI-A; digest 3.4): a robot drives along
// a line from x = 0 to about 3 m in 50 steps, measuring its displacement (variance 1e-2 m²) and the signed
// offsets m − x of the landmarks 0.5–6 m ahead (variance 1e-4 m²), each detected with p_D 0.9, with Poisson
// clutter of intensity 0.01 per metre over that interval (λ_c = 0.055 per scan) unless a clutter rate is
// given. Five landmarks lie in x ∈ [3, 8] m. The paper gives neither the speed profile nor the layout; this
// reconstruction [IMPL] drives at a constant 0.06 m per step and places landmark i at 3.5 + i m ± 0.3 m. Each
// data seed is one Monte Carlo realisation; every measurement keeps the index of the landmark that made it
// (−1 for clutter), which the RFS solver never reads.
#include <cstdint>
#include <vector>

namespace glmbslam::sim {

struct LineScenario {
  std::vector<double> poses;     ///< true x_k, k = 0..K−1
  std::vector<double> controls;  ///< measured displacements u_k (u_0 = 0, unused)
  std::vector<double> landmarks;
  std::vector<std::vector<double>> measurements;      ///< Z_k: offsets m − x_k with noise, and clutter
  std::vector<std::vector<int>> measurement_sources;  ///< landmark index per measurement, −1 = clutter
  double odometry_variance = 1e-2;                    ///< m² per step
  double measurement_variance = 1e-4;                 ///< m²
  double min_range = 0.5, max_range = 6.0;            ///< the sensor's interval ahead (m)
  double detection_probability = 0.9;
  double clutter_rate = 0.0;  ///< λ_c per scan
  std::size_t steps() const { return poses.size(); }
};

struct Paper004LineOptions {
  double clutter_rate = -1.0;   ///< λ_c per scan; < 0 = the paper's intensity 0.01 per metre (0.055)
  std::uint64_t data_seed = 0;  ///< the data realisation
};

/// Builds the scenario (deterministic for given options).
LineScenario make_paper004_line_scenario(const Paper004LineOptions& options = {});

}  // namespace glmbslam::sim
