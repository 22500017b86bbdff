#pragma once
// Paper 000's simulation (δ-GLMB-SLAM 2.0, Sensors 2019; digest 0.3): 23 landmarks, a robot driving a
// pre-planned loop at 1 m/s, a 360° range-bearing sensor to 3 m, p_D 0.7, Poisson clutter λ_c ∈ {1, 5, 10,
// 15}.
//
// The paper gives the parameters but not the path or the landmark layout; this reconstruction [IMPL]:
//  - the steering ("bicycle") motion model of the simulator family the paper uses (control (v, G), σ_v = 0.1
//  m/s,
//    σ_G = 2° exactly as Table 1), wheel base L = 1 m, dt = 0.25 s (backend/models/steering_motion.hpp);
//  - the path is a rounded rectangle: straights of 26 and 12 steps (6.5 m, 3 m) and 90° left turns of 12
//  steps
//    each (G = asin(π/24 · L/(v dt)) ≈ 31.6°, radius ≈ 1.9 m), 124 steps per lap, closed exactly; after the
//    lap the robot re-drives 27 steps, so the loop closure happens at steps 124–151 (the paper: 125–150). 152
//    poses (steps 0..151) in total;
//  - 23 landmarks spread evenly along the lap, alternately left and right of the path at 0.8–1.8 m (seeded
//    jitter); measurement noise σ_r = 0.05 m, σ_b = 0.5°;
//  - one data realisation per clutter rate, as in the paper: the odometry noise and the landmark detections
//  and
//    their noise come from one stream (the same for every λ_c); the clutter of each λ_c from its own stream.
#include <cstdint>

#include "sim/scenario2d.hpp"

namespace glmbslam::sim {

struct Paper2019Options {
  double clutter_rate = 5.0;       ///< λ_c per scan
  std::uint64_t data_seed = 2019;  ///< the single data realisation
  double dt = 0.25;                ///< [s]
  double speed = 1.0;              ///< [m/s]
  double sigma_speed = 0.1;        ///< [m/s]
  double sigma_steer_deg = 2.0;    ///< [°]
  double wheel_base = 1.0;         ///< [m]
  double sigma_range = 0.05;       ///< [m]
  double sigma_bearing_deg = 0.5;  ///< [°]
  double max_range = 3.0;          ///< [m]
  double detection_probability = 0.7;
};

/// Builds the scenario (deterministic for given options). Throws std::invalid_argument for a negative clutter
/// rate.
Scenario2D make_paper2019_scenario(const Paper2019Options& options = {});

/// The clutter rates of the paper's comparison.
inline constexpr double kPaper2019ClutterRates[] = {1.0, 5.0, 10.0, 15.0};

}  // namespace glmbslam::sim
