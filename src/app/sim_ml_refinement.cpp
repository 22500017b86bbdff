#include "app/sim_ml_refinement.hpp"

#include "backend/mlslam/rfs_ml_slam.hpp"
#include "core/interrupt.hpp"

namespace glmbslam::app {

namespace {

template <class Motion>
using Slam = backend::RfsMlSlam<Motion, backend::RangeBearingModel>;

template <class Motion>
struct Inputs {
  typename Slam<Motion>::ControlList controls;
  std::vector<typename Slam<Motion>::MeasurementSet> scans;
  explicit Inputs(const sim::Scenario2D& s) {
    for (const auto& u : s.controls) controls.push_back(u);
    for (const auto& z : s.measurements) scans.emplace_back(z.begin(), z.end());
  }
};

template <class Motion>
MlSimResult result_of(const typename Slam<Motion>::PoseList& poses,
                      const typename Slam<Motion>::LandmarkList& map, const backend::MlSlamReport& r) {
  MlSimResult out;
  out.poses.assign(poses.begin(), poses.end());
  out.map.assign(map.begin(), map.end());
  out.ms = r.ms;
  out.rounds = r.rounds;
  out.log_likelihood = r.final_log_likelihood;
  out.interrupted = r.stopped;
  return out;
}

}  // namespace

template <class Motion>
MlSimResult run_mlslam(const Motion& motion, const backend::RangeBearingModel& model,
                       const sim::Scenario2D& s, const backend::MlSlamConfig& config) {
  const Inputs<Motion> in(s);
  typename Slam<Motion>::PoseList poses;
  typename Slam<Motion>::LandmarkList map;
  Slam<Motion> slam(motion, model, config);
  slam.set_stop([] { return interrupt_requested(); });
  const auto r = slam.solve_from_odometry(s.initial_pose(), in.controls, in.scans, poses, map);
  return result_of<Motion>(poses, map, r);
}

template <class Motion>
MlSimResult refine_ml(const Motion& motion, const backend::RangeBearingModel& model, const sim::Scenario2D& s,
                      const backend::MlSlamConfig& config, const std::vector<Eigen::Vector3d>& poses,
                      const std::vector<Eigen::Vector2d>& map) {
  const Inputs<Motion> in(s);
  typename Slam<Motion>::PoseList x(poses.begin(), poses.end());
  typename Slam<Motion>::LandmarkList m(map.begin(), map.end());
  Slam<Motion> slam(motion, model, config);
  slam.set_stop([] { return interrupt_requested(); });
  const auto r = slam.solve(x, in.controls, in.scans, m);
  return result_of<Motion>(x, m, r);
}

template MlSimResult run_mlslam(const backend::UnicycleMotion&, const backend::RangeBearingModel&,
                                const sim::Scenario2D&, const backend::MlSlamConfig&);
template MlSimResult run_mlslam(const backend::SteeringMotion&, const backend::RangeBearingModel&,
                                const sim::Scenario2D&, const backend::MlSlamConfig&);
template MlSimResult refine_ml(const backend::UnicycleMotion&, const backend::RangeBearingModel&,
                               const sim::Scenario2D&, const backend::MlSlamConfig&,
                               const std::vector<Eigen::Vector3d>&, const std::vector<Eigen::Vector2d>&);
template MlSimResult refine_ml(const backend::SteeringMotion&, const backend::RangeBearingModel&,
                               const sim::Scenario2D&, const backend::MlSlamConfig&,
                               const std::vector<Eigen::Vector3d>&, const std::vector<Eigen::Vector2d>&);

}  // namespace glmbslam::app
