#pragma once
// How `glmbslam sim` scores a map: OSPA / GOSPA against the ground-truth landmarks seen (in the field of view
// of the true pose) so far.
#include <vector>

#include "app/sim_run_record.hpp"
#include "eval/ospa.hpp"
#include "sim/scenario2d.hpp"

namespace glmbslam::app {

inline constexpr double kSimOspaC = 0.5, kSimOspaP = 1.0;     // paper 000
inline constexpr double kSimGospaC = 20.0, kSimGospaP = 2.0;  // paper 003 (α = 2)

/// Ground-truth landmarks seen (in the field of view of the true pose) at any step ≤ k, for every k.
std::vector<std::vector<int>> seen_so_far(const sim::Scenario2D& s);

/// The landmarks `ids` of `s` as a 2×N point set.
eval::PointSet truth_set(const sim::Scenario2D& s, const std::vector<int>& ids);

/// OSPA, GOSPA and the cardinality error of rec.final_map against the landmarks seen during the run.
void score_final_map(SimRunRecord& rec, const sim::Scenario2D& s, const std::vector<std::vector<int>>& seen);

}  // namespace glmbslam::app
