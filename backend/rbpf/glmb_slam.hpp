#pragma once
// δ-GLMB-SLAM (paper 000): a Rao–Blackwellised particle filter whose particles each carry a trajectory and a
// δ-GLMB landmark map. Usage: see backend/rbpf/README.md.
//
// Per step k (first call of step() is k = 1), for every particle in parallel with its own RandomStream
// (seed, k, particle index) — so the output does not depend on the thread count:
//   proposal "prior":   x ~ f(·|x⁻, u) (δ-GLMB-SLAM 1.0)
//   proposal "optimal": x ~ q = the optimal-kernel Gaussian (optimal_proposal.hpp; δ-GLMB-SLAM 2.0)
//   proposal "mh":      x ~ q = the multi-hypothesis importance density of paper 003 (mh_proposal.hpp,
//   settings
//                       passed to the constructor), built ONCE PER PARENT: particles that are resampled
//                       copies of one parent (same trajectory node and map) share one build — exact, since
//                       the build draws no random numbers; log q is the full mixture density
//   map: δ-GLMB joint prediction/update at x (glmb_update.hpp) → new map, log Ĝ(x)
//   weight "importance": log w += log Ĝ(x) + log f(x|x⁻,u) − log q(x)   (= log Ĝ for the prior proposal)
//   weight "paper":      log w += log Σ_{h,θ} W_{h,θ}   (Eq. 33 as printed; log Ĝ for the prior proposal)
// then normalisation, the estimate (highest-weight particle, taken before resampling), and systematic
// resampling every step ("always") or when ESS < ess_threshold·N ("ess"): the particle-step skeleton of
// particle_set.hpp, shared with the other filters. Trajectories and maps are shared between particles through
// shared_ptr, so resampling copies pointers.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/glmb_update.hpp"
#include "backend/rbpf/labelled_map_filter.hpp"
#include "backend/rbpf/mh_per_parent.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "backend/rbpf/particle_set.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::backend {

/// What happened in one step (for the Monte Carlo statistics).
struct StepReport {
  int step = 0;
  double ess = 0.0;  ///< effective sample size 1/Σw² after the weight update (before resampling)
  bool resampled = false;
  double ms = 0.0;              ///< wall time of step()
  int best_particle = 0;        ///< index of the highest-weight particle (before resampling)
  int hypotheses = 0;           ///< map hypotheses of the best particle
  int tracks = 0;               ///< tracks in the best particle's track table
  int active_tracks = 0;        ///< tracks in view of the best particle
  double log_likelihood = 0.0;  ///< log Ĝ of the best particle
};

template <class Motion, class Meas>
class GlmbSlam {
 public:
  using State = typename Motion::State;
  using Control = typename Motion::Control;
  using Tangent = typename Motion::Tangent;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = GlmbMap<Meas>;
  using Node = TrajectoryNode<State>;
  using LandmarkList = std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>>;
  using PoseList = std::vector<State, Eigen::aligned_allocator<State>>;
  using Particle = RbpfParticle<State, Map>;

  /// Throws ConfigError on an invalid config. `mh` configures proposal "mh" (ignored otherwise).
  GlmbSlam(const Motion& motion, const Meas& model, const RbpfConfig& config, const State& initial_pose,
           const MhProposalConfig& mh = MhProposalConfig())
      : motion_(motion),
        model_(model),
        config_(validated(config)),
        updater_(model, config.glmb),
        proposal_(motion, model, config),
        mh_(motion, model, mh),
        weighting_(config),
        // the empty map is created non-const: recyclable
        set_(config.particles, config.seed,
             ResamplingPolicy::parse(config.resampling, config.ess_threshold, "rbpf.resampling"),
             initial_pose, std::make_shared<Map>(Map::empty())) {}

  /// Optional, before the first step: the measurement set Z_0 taken at the (known) initial pose. It updates
  /// the common initial map (so its measurements become birth candidates for step 1), anchoring the map to
  /// the initial pose. Throws InputError on a non-finite measurement, std::logic_error after step().
  void initial_scan(const MeasurementSet& Z) {
    backend::initial_scan(set_, updater_, Z, config_.seed, "GlmbSlam");
  }

  /// One filter step with control u (from step k−1 to k) and the measurement set Z_k.
  /// Throws InputError (and leaves the filter unchanged) if a measurement or the control is not finite.
  void step(const Control& u, const MeasurementSet& Z) {
    Stopwatch watch;
    const int k = begin_step(set_, updater_, u, Z);
    const std::size_t n = set_.particles().size();
    stats_.resize(n);
    const bool mh = config_.proposal == "mh";
    if (mh) mh_.build(set_.particles(), u, Z);
    // the posterior maps: storage of maps no longer referenced (recycled at the end of the previous step,
    // keeping the capacity of their vectors) or new ones
    fresh_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!pool_.empty()) {
        fresh_[i] = std::move(pool_.back());
        pool_.pop_back();
      } else {
        fresh_[i] = std::make_shared<Map>();
      }
    }
    retired_.clear();
    for (const auto& p : set_.particles()) retired_.push_back(p.map);
    map_log_.resize(n);
    auto propagate = [&](std::size_t i, RandomStream& rng, const Particle& p, Particle& out) {
      State x;
      State x_estimate;
      double log_increment;
      if (mh) {  // the parent's MH-ID (shared by its resampled copies)
        log_increment = mh_.sample(i, rng, x, x_estimate);
      } else {
        auto view = [&]() -> const Map& { return *p.map; };
        log_increment =
            draw_pose(weighting_, motion_, proposal_, view, p.trajectory->pose, u, Z, rng, x, x_estimate);
      }
      std::shared_ptr<Map> map = std::move(fresh_[i]);
      const GlmbUpdateStats s = updater_.update(*p.map, x, Z, k, rng, *map);
      map_log_[i] = weighting_.map_factor(s);
      log_increment += map_log_[i];
      out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
      out.map = std::move(map);
      stats_[i] = s;
      return log_increment;
    };
    auto adjust = [&](std::vector<Particle>& next) {
      if (weighting_.sibling_mean) pool_sibling_normalizers(map_log_, next, pool_scratch_);
    };
    const ParticleStepResult r =
        set_.step(propagate, adjust, [&](const std::vector<Particle>& next, const ParticleStepResult&) {
          weighted_mean_ = weighted_mean(next);
        });
    // the previous maps no particle uses any more go to the pool (each once; the const_pointer_cast is
    // sound: every map here was created non-const by this class)
    std::sort(retired_.begin(), retired_.end(),
              [](const auto& a, const auto& b) { return std::less<const Map*>()(a.get(), b.get()); });
    retired_.erase(std::unique(retired_.begin(), retired_.end()), retired_.end());
    for (auto& m : retired_)
      if (m.use_count() == 1) pool_.push_back(std::const_pointer_cast<Map>(std::move(m)));
    retired_.clear();
    StepReport report;
    report.step = k;
    report.ess = r.ess;
    report.best_particle = static_cast<int>(r.best);
    report.hypotheses = stats_[r.best].hypotheses;
    report.tracks = stats_[r.best].tracks;
    report.active_tracks = stats_[r.best].active_tracks;
    report.log_likelihood = stats_[r.best].log_normalizer;
    report.resampled = r.resampled;
    report.ms = watch.elapsed_ms();
    last_ = report;
  }

  /// A step (k−1 → k, control u) whose sensor saw nothing: the poses move, the maps stay (blind_step in
  /// labelled_map_filter.hpp). Throws InputError (and leaves the filter unchanged) if u is not finite.
  void blind_step(const Control& u) {
    Stopwatch watch;
    const ParticleStepResult r = backend::blind_step(set_, motion_, u);
    weighted_mean_ = weighted_mean(set_.particles());
    record_blind_step(last_, r, watch.elapsed_ms());
  }

  // ----- estimates (taken from the highest-weight particle before resampling) -----
  /// The estimated pose at the last step (highest-weight particle).
  const State& pose() const { return set_.pose(); }
  /// The weighted mean pose at the last step (mean in the tangent space at the best pose).
  const State& mean_pose() const { return set_.steps() == 0 ? set_.pose() : weighted_mean_; }
  /// The highest-weight particle's trajectory, steps 0..k.
  PoseList trajectory() const { return set_.trajectory(); }
  /// The highest-weight particle's Rao–Blackwellised estimates, steps 0..k: at each step the mean of the
  /// optimal-kernel proposal given that particle's history and map (its sampled pose for the prior proposal).
  /// Free of the sampling noise of trajectory(), which the particle's map is conditioned on.
  PoseList estimated_trajectory() const { return set_.estimated_trajectory(); }
  /// The highest-weight particle's map estimate (MAP cardinality, then its best hypothesis).
  LandmarkList landmarks() const { return estimate_map(*set_.best().map); }
  /// The highest-weight particle's map (all hypotheses).
  const Map& map() const { return *set_.best().map; }

  const StepReport& last_report() const { return last_; }
  int steps() const { return set_.steps(); }
  int resample_count() const { return set_.resample_count(); }
  const std::vector<Particle>& particles() const { return set_.particles(); }
  const RbpfConfig& config() const { return config_; }

 private:
  static const RbpfConfig& validated(const RbpfConfig& config) {
    if (config.particles < 1) throw ConfigError("rbpf.particles must be at least 1");
    if (config.proposal != "prior" && config.proposal != "optimal" && config.proposal != "mh")
      throw ConfigError("rbpf.proposal must be 'prior', 'optimal' or 'mh'");
    validate_rbpf_weighting(config);
    if (config.proposal == "mh" && config.weighting != "importance")
      throw ConfigError("rbpf.proposal 'mh' needs rbpf.weighting 'importance'");
    if (config.resampling != "always" && config.resampling != "ess")
      throw ConfigError("rbpf.resampling must be 'always' or 'ess'");
    return config;
  }

  State weighted_mean(const std::vector<Particle>& ps) const {
    const State& ref = set_.pose();
    Tangent d = Tangent::Zero();
    for (const auto& p : ps) d += std::exp(p.log_weight) * Motion::local(p.trajectory->pose, ref);
    return Motion::retract(ref, d);
  }

  Motion motion_;
  Meas model_;
  RbpfConfig config_;
  GlmbUpdater<Meas> updater_;
  OptimalProposal<Motion, Meas> proposal_;
  MhPerParent<Motion, Meas> mh_;  ///< proposal "mh"
  ProposalWeighting weighting_;   ///< proposal / weighting / normaliser flags
  ParticleSet<State, Map> set_;
  std::vector<std::shared_ptr<Map>> fresh_, pool_;   ///< posterior maps of this step; recyclable maps
  std::vector<std::shared_ptr<const Map>> retired_;  ///< the previous step's maps, checked for reuse
  std::vector<GlmbUpdateStats> stats_;
  State weighted_mean_;
  std::vector<double> map_log_;  ///< this step's child i: its map factor log Ĝ (sibling_mean)
  std::vector<double> pool_scratch_;
  StepReport last_;
};

}  // namespace glmbslam::backend
