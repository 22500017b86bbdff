#include "app/sim_filter_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <spdlog/spdlog.h>

#include "app/baseline_filters.hpp"
#include "app/sim_map_scoring.hpp"
#include "app/sim_ml_refinement.hpp"
#include "app/sim_models.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/steering_motion.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/phd/phd_slam.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "core/interrupt.hpp"
#include "core/stopwatch.hpp"
#include "eval/ospa.hpp"

namespace glmbslam::app {

namespace {

using backend::RangeBearingModel;

template <class LandmarkList>
eval::PointSet estimate_set(const LandmarkList& lms) {
  eval::PointSet y(2, static_cast<Eigen::Index>(lms.size()));
  for (std::size_t i = 0; i < lms.size(); ++i)
    y.col(static_cast<Eigen::Index>(i)) = lms[i].mean.template head<2>();
  return y;
}

/// Drives one filter over the scenario (steps 1..K−1 with u_k and Z_k).
template <class Slam>
SimRunRecord drive(Slam& slam, const sim::Scenario2D& s, const std::vector<std::vector<int>>& seen,
                   bool per_step_ospa, int particles) {
  SimRunRecord rec;
  rec.estimates.push_back(s.poses[0]);
  typename Slam::MeasurementSet z(s.measurements[0].begin(), s.measurements[0].end());
  set_true_labels(slam, s.measurement_sources[0], 0);  // FastSLAM 2.0 with known associations only
  slam.initial_scan(z);  // Z_0 at the known initial pose: births for step 1, anchoring the map
  for (std::size_t k = 1; k < s.steps(); ++k) {
    if (interrupt_requested()) throw SimRunInterrupted{};
    z.assign(s.measurements[k].begin(), s.measurements[k].end());
    set_true_labels(slam, s.measurement_sources[k], 0);
    slam.step(s.controls[k], z);
    rec.estimates.push_back(slam.pose());
    const auto& r = slam.last_report();
    rec.ms.push_back(r.ms);
    rec.ess_fraction.push_back(r.ess / static_cast<double>(particles));
    rec.resampled += r.resampled ? 1 : 0;
    if (per_step_ospa) {
      const auto lms = slam.landmarks();
      const eval::PointSet truth = truth_set(s, seen[k]), est = estimate_set(lms);
      rec.ospa.push_back(eval::ospa(truth, est, kSimOspaC, kSimOspaP).distance);
      rec.gospa.push_back(eval::gospa(truth, est, kSimOspaC, kSimOspaP).distance);
      rec.cardinality.push_back(static_cast<double>(lms.size()));
    }
  }
  for (const auto& l : slam.landmarks()) rec.final_map.emplace_back(l.mean.template head<2>());
  score_final_map(rec, s, seen);
  return rec;
}

/// An ML solution (standalone or refinement) as the run's estimate; an interrupted solve ends the run as an
/// interrupted filter step does. A refinement keeps the filter's estimate and scores beside it.
void apply_ml(SimRunRecord& rec, const MlSimResult& ml, const sim::Scenario2D& s,
              const std::vector<std::vector<int>>& seen, bool refinement) {
  if (ml.interrupted) throw SimRunInterrupted{};
  spdlog::debug("RFS-ML: {} rounds, log-likelihood {:.3f}, {:.0f} ms", ml.rounds, ml.log_likelihood, ml.ms);
  double se = 0.0;
  for (std::size_t k = 1; k < s.steps(); ++k) se += (rec.estimates[k] - s.poses[k]).head<2>().squaredNorm();
  rec.filter_position_rmse = std::sqrt(se / static_cast<double>(std::max<std::size_t>(s.steps() - 1, 1)));
  rec.filter_gospa = rec.final_gospa.distance;
  if (refinement) rec.filter_estimates = rec.estimates;
  rec.estimates = ml.poses;
  rec.final_map = ml.map;
  rec.ml_ms = ml.ms;
  score_final_map(rec, s, seen);
}

/// Dead reckoning (the floor): the odometry integrated with the motion model, no map.
template <class Motion>
class DeadReckoning {
 public:
  using MeasurementSet = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;
  struct Report {
    double ess = 1.0;
    bool resampled = false;
    double ms = 0.0;
  };
  struct Landmark {
    Eigen::Vector2d mean;
  };
  DeadReckoning(const Motion& motion, const Eigen::Vector3d& x0) : motion_(motion), x_(x0) {}
  void initial_scan(const MeasurementSet&) {}
  void step(const typename Motion::Control& u, const MeasurementSet&) {
    Stopwatch w;
    x_ = motion_.predict(x_, u);
    report_.ms = w.elapsed_ms();
  }
  const Eigen::Vector3d& pose() const { return x_; }
  const Report& last_report() const { return report_; }
  std::vector<Landmark> landmarks() const { return {}; }

 private:
  Motion motion_;
  Eigen::Vector3d x_;
  Report report_;
};

/// The recursive filters (everything but mlslam).
template <class Motion>
SimRunRecord run_recursive_filter(const Motion& motion, const RangeBearingModel& model,
                                  const sim::Scenario2D& s, const SimOptions& o, SimFilters f, int run,
                                  const std::vector<std::vector<int>>& seen) {
  const std::uint64_t seed = *o.seed * 1000003ULL + static_cast<std::uint64_t>(run);
  const bool ospa_steps = o.scenario == "paper2019";
  if (o.algorithm == "dr") {
    DeadReckoning<Motion> dr(motion, s.initial_pose());
    return drive(dr, s, seen, ospa_steps, 1);
  }
  if (o.algorithm == "phd1" || o.algorithm == "phd3") {
    backend::PhdConfig& phd = o.algorithm == "phd3" ? f.phd3 : f.phd;
    phd.particles = *o.particles;
    phd.seed = seed;
    phd.proposal = o.algorithm == "phd3" ? "mh" : "prior";
    backend::PhdSlam<Motion, RangeBearingModel> slam(motion, model, phd, s.initial_pose(), f.mh);
    return drive(slam, s, seen, ospa_steps, *o.particles);
  }
  f.rbpf.particles = *o.particles;
  f.rbpf.seed = seed;
  if (is_baseline_algorithm(o.algorithm)) {
    return with_baseline_filter<Motion>(
        o.algorithm, motion, model, f.rbpf, f.baselines, s.initial_pose(),
        [&](auto& slam) { return drive(slam, s, seen, ospa_steps, *o.particles); });
  }
  f.rbpf.proposal = o.algorithm == "glmb1" ? "prior" : o.algorithm == "glmb_mh" ? "mh" : "optimal";
  backend::GlmbSlam<Motion, RangeBearingModel> slam(motion, model, f.rbpf, s.initial_pose(), f.mh);
  return drive(slam, s, seen, ospa_steps, *o.particles);
}

template <class Motion>
SimRunRecord run_filter(const Motion& motion, const RangeBearingModel& model, const sim::Scenario2D& s,
                        const SimOptions& o, const SimFilters& f, int run,
                        const std::vector<std::vector<int>>& seen) {
  if (o.algorithm == "mlslam") {
    SimRunRecord rec;
    rec.estimates.assign(s.steps(), s.initial_pose());
    apply_ml(rec, run_mlslam(motion, model, s, f.ml), s, seen, false);
    rec.ms.assign(s.steps() - 1, rec.ml_ms / static_cast<double>(std::max<std::size_t>(s.steps() - 1, 1)));
    return rec;
  }
  SimRunRecord rec = run_recursive_filter(motion, model, s, o, f, run, seen);
  if (o.refine == "ml")
    apply_ml(rec, refine_ml(motion, model, s, f.ml, rec.estimates, rec.final_map), s, seen, true);
  return rec;
}

}  // namespace

SimRunRecord run_sim_filter(const sim::Scenario2D& s, const SimOptions& o, const SimFilters& f, int run) {
  const auto seen = seen_so_far(s);
  const RangeBearingModel model = sim_measurement_model(s);
  if (s.motion == sim::MotionKind::kSteering)
    return run_filter(backend::SteeringMotion(sim_steering_config(s)), model, s, o, f, run, seen);
  return run_filter(backend::UnicycleMotion(sim_unicycle_config(s)), model, s, o, f, run, seen);
}

}  // namespace glmbslam::app
