#pragma once
// The models `glmbslam sim` hands its filters and the RFS-ML solver for a 2D scenario: the range-bearing
// sensor and the motion model of the generator (src/sim), so that on the synthetic benchmarks the models are
// exact. Used by sim_filter_run.cpp and the micro-benchmarks (bench/).
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/steering_motion.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "sim/scenario2d.hpp"

namespace glmbslam::app {

/// The sensor of `s` (noise, range, field of view, p_D, clutter rate over its (range, bearing) volume).
backend::RangeBearingModel sim_measurement_model(const sim::Scenario2D& s);

/// The unicycle of `s` (Euler step, as the generator; σ_v, σ_ω from its control noise).
backend::UnicycleMotionConfig sim_unicycle_config(const sim::Scenario2D& s);

/// The steering (bicycle) model of `s`, for scenarios with MotionKind::kSteering.
backend::SteeringMotionConfig sim_steering_config(const sim::Scenario2D& s);

}  // namespace glmbslam::app
