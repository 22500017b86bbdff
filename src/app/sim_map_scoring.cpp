#include "app/sim_map_scoring.hpp"

namespace glmbslam::app {

std::vector<std::vector<int>> seen_so_far(const sim::Scenario2D& s) {
  std::vector<std::vector<int>> out(s.steps());
  std::vector<char> seen(s.landmarks.size(), 0);
  std::vector<int> list;
  for (std::size_t k = 0; k < s.steps(); ++k) {
    for (int i : sim::visible_landmarks(s.poses[k], s.landmarks, s.sensor)) {
      if (seen[static_cast<std::size_t>(i)] == 0) {
        seen[static_cast<std::size_t>(i)] = 1;
        list.push_back(i);
      }
    }
    out[k] = list;
  }
  return out;
}

eval::PointSet truth_set(const sim::Scenario2D& s, const std::vector<int>& ids) {
  eval::PointSet x(2, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t i = 0; i < ids.size(); ++i) {
    x.col(static_cast<Eigen::Index>(i)) = s.landmarks[static_cast<std::size_t>(ids[i])];
  }
  return x;
}

void score_final_map(SimRunRecord& rec, const sim::Scenario2D& s, const std::vector<std::vector<int>>& seen) {
  eval::PointSet est(2, static_cast<Eigen::Index>(rec.final_map.size()));
  for (std::size_t i = 0; i < rec.final_map.size(); ++i)
    est.col(static_cast<Eigen::Index>(i)) = rec.final_map[i];
  const eval::PointSet truth = truth_set(s, seen.back());
  rec.final_ospa = eval::ospa(truth, est, kSimOspaC, kSimOspaP);
  rec.final_gospa = eval::gospa(truth, est, kSimGospaC, kSimGospaP);
  rec.final_cardinality_error = static_cast<int>(rec.final_map.size()) - static_cast<int>(seen.back().size());
}

}  // namespace glmbslam::app
