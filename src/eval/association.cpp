#include "eval/association.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/error.hpp"

namespace glmbslam::eval {

AssociatedTrajectories associate_by_index(const PoseList& gt, const PoseList& est,
                                          const std::string& est_path) {
  if (gt.size() != est.size()) {
    throw InputError(est_path, "has " + std::to_string(est.size()) + " poses but the ground truth has " +
                                   std::to_string(gt.size()) + " (KITTI files must have one pose per frame)");
  }
  if (gt.empty()) throw InputError(est_path, "no poses to evaluate");
  AssociatedTrajectories a;
  a.gt = gt;
  a.est = est;
  return a;
}

AssociatedTrajectories associate_by_timestamp(const io::Trajectory& gt, const io::Trajectory& est,
                                              double tolerance_s, const std::string& est_path) {
  if (gt.timestamps.size() != gt.poses.size() || est.timestamps.size() != est.poses.size()) {
    throw InputError(est_path, "timestamps missing for association (use --format tum with TUM files)");
  }
  AssociatedTrajectories a;
  size_t g = 0;  // first ground-truth stamp not yet used
  for (size_t i = 0; i < est.poses.size(); ++i) {
    const double t = est.timestamps[i];
    // Advance to the last unused gt stamp ≤ t, then choose the nearer of it and its successor.
    while (g + 1 < gt.timestamps.size() && gt.timestamps[g + 1] <= t) ++g;
    size_t best = g;
    if (g < gt.timestamps.size() && g + 1 < gt.timestamps.size() &&
        std::abs(gt.timestamps[g + 1] - t) < std::abs(gt.timestamps[g] - t)) {
      best = g + 1;
    }
    if (best >= gt.timestamps.size() || std::abs(gt.timestamps[best] - t) > tolerance_s) {
      ++a.unmatched_est;
      continue;
    }
    a.gt.push_back(gt.poses[best]);
    a.est.push_back(est.poses[i]);
    a.timestamps.push_back(gt.timestamps[best]);
    g = best + 1;  // one-to-one
    if (g >= gt.timestamps.size()) {
      a.unmatched_est += static_cast<int>(est.poses.size() - i - 1);
      break;
    }
  }
  if (a.gt.size() < 2) {
    // the two time ranges tell a unit or clock offset (ns against s, a shifted start) from a tolerance issue
    std::ostringstream why;
    why << "fewer than 2 poses match a ground-truth timestamp within " << tolerance_s << " s";
    if (!est.timestamps.empty() && !gt.timestamps.empty()) {
      why << " (estimate " << std::fixed << std::setprecision(3) << est.timestamps.front() << "…"
          << est.timestamps.back() << " s, ground truth " << gt.timestamps.front() << "…"
          << gt.timestamps.back() << " s; --tolerance sets the window)";
    }
    throw InputError(est_path, why.str());
  }
  return a;
}

}  // namespace glmbslam::eval
