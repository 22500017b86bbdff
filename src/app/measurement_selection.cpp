#include "app/measurement_selection.hpp"

#include <algorithm>
#include <stdexcept>

namespace glmbslam::app {

std::vector<int> select_measurements(const frontend::StereoMeasurementList& measurements,
                                     const SelectionGrid& grid, const SelectionRules& rules,
                                     const std::vector<char>& preferred) {
  const int max_count = rules.max_count;
  const int cells = grid.columns * grid.rows;
  std::vector<std::vector<int>> per_cell(static_cast<std::size_t>(cells));
  for (int i = 0; i < static_cast<int>(measurements.size()); ++i) {
    const auto& m = measurements[static_cast<std::size_t>(i)];
    const double depth = m.point.z();
    if (!(depth >= rules.min_depth && depth <= rules.max_depth) || !m.z.allFinite()) continue;
    if (m.octave > rules.max_octave) continue;
    const int cx = std::clamp(static_cast<int>(m.z.x() / grid.width * grid.columns), 0, grid.columns - 1);
    const int cy = std::clamp(static_cast<int>(m.z.y() / grid.height * grid.rows), 0, grid.rows - 1);
    per_cell[static_cast<std::size_t>(cy * grid.columns + cx)].push_back(i);
  }
  for (auto& cell : per_cell) {
    auto is_preferred = [&](int i) {
      return !preferred.empty() && preferred[static_cast<std::size_t>(i)] != 0;
    };
    std::stable_sort(cell.begin(), cell.end(), [&](int a, int b) {
      if (is_preferred(a) != is_preferred(b)) return is_preferred(a);
      return measurements[static_cast<std::size_t>(a)].response >
             measurements[static_cast<std::size_t>(b)].response;
    });
  }
  std::vector<int> selected;
  for (std::size_t round = 0; static_cast<int>(selected.size()) < max_count; ++round) {
    bool any = false;
    for (const auto& cell : per_cell) {
      if (round < cell.size()) {
        any = true;
        selected.push_back(cell[round]);
        if (static_cast<int>(selected.size()) >= max_count) break;
      }
    }
    if (!any) break;
  }
  return selected;
}

std::vector<char> tracked_from(const std::vector<int>& previous_measurement,
                               const std::vector<char>& previous_flags) {
  std::vector<char> tracked(previous_measurement.size(), 0);
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    const int prev = previous_measurement[i];
    tracked[i] = prev >= 0 && static_cast<std::size_t>(prev) < previous_flags.size() &&
                 previous_flags[static_cast<std::size_t>(prev)];
  }
  return tracked;
}

std::vector<char> control_exclusion(const std::string& mode, const std::vector<char>& selected,
                                    const std::vector<char>& tracked_selected) {
  if (mode == "none") return std::vector<char>(selected.size(), 0);
  if (mode == "selected") return selected;
  if (mode != "tracked") throw std::invalid_argument("control_exclusion: unknown mode '" + mode + "'");
  std::vector<char> excluded(selected.size(), 0);
  for (std::size_t i = 0; i < excluded.size(); ++i)
    excluded[i] = selected[i] && i < tracked_selected.size() && tracked_selected[i];
  return excluded;
}

}  // namespace glmbslam::app
