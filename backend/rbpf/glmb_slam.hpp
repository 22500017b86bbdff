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
// resampling every step ("always") or when ESS < ess_threshold·N ("ess"). Trajectories and maps are shared
// between particles through shared_ptr, so resampling copies pointers.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/glmb_update.hpp"
#include "backend/rbpf/mh_per_parent.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "backend/rbpf/resampling.hpp"
#include "backend/rbpf/trajectory.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/parallel.hpp"
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

  struct Particle {
    double log_weight = 0.0;  ///< normalised
    std::shared_ptr<const Node> trajectory;
    std::shared_ptr<const Map> map;
  };

  /// Throws ConfigError on an invalid config. `mh` configures proposal "mh" (ignored otherwise).
  GlmbSlam(const Motion& motion, const Meas& model, const RbpfConfig& config, const State& initial_pose,
           const MhProposalConfig& mh = MhProposalConfig())
      : motion_(motion),
        model_(model),
        config_(config),
        updater_(model, config.glmb),
        proposal_(motion, model, config),
        mh_(motion, model, mh),
        factorized_(config.particle_normalizer == "factorized") {
    if (config.particles < 1) throw ConfigError("rbpf.particles must be at least 1");
    if (config.proposal != "prior" && config.proposal != "optimal" && config.proposal != "mh")
      throw ConfigError("rbpf.proposal must be 'prior', 'optimal' or 'mh'");
    if (config.weighting != "importance" && config.weighting != "paper")
      throw ConfigError("rbpf.weighting must be 'importance' or 'paper'");
    if (config.proposal == "mh" && config.weighting != "importance")
      throw ConfigError("rbpf.proposal 'mh' needs rbpf.weighting 'importance'");
    if (config.resampling != "always" && config.resampling != "ess")
      throw ConfigError("rbpf.resampling must be 'always' or 'ess'");
    if (config.particle_normalizer != "sampled" && config.particle_normalizer != "factorized")
      throw ConfigError("rbpf.particle_normalizer must be 'sampled' or 'factorized'");
    if (config.single_particle != "sample" && config.single_particle != "mean")
      throw ConfigError("rbpf.single_particle must be 'sample' or 'mean'");
    auto root = std::make_shared<const Node>(initial_pose, 0, nullptr);
    std::shared_ptr<const Map> empty = std::make_shared<Map>(Map::empty());  // non-const: recyclable
    const double log_w = -std::log(static_cast<double>(config.particles));
    particles_.assign(config.particles, Particle{log_w, root, empty});
    best_ = particles_[0];
  }

  /// Optional, before the first step: the measurement set Z_0 taken at the (known) initial pose. It updates
  /// the common initial map (so its measurements become birth candidates for step 1), anchoring the map to
  /// the initial pose. Throws InputError on a non-finite measurement, std::logic_error after step().
  void initial_scan(const MeasurementSet& Z) {
    if (step_ != 0) throw std::logic_error("GlmbSlam::initial_scan must be called before the first step");
    updater_.validate(Z, 0);
    RandomStream rng(config_.seed, 0xFFFFFFULL);
    auto map = std::make_shared<Map>();
    updater_.update(*particles_[0].map, particles_[0].trajectory->pose, Z, 0, rng, *map);
    std::shared_ptr<const Map> shared = std::move(map);
    for (auto& p : particles_) p.map = shared;
    best_ = particles_[0];
  }

  /// One filter step with control u (from step k−1 to k) and the measurement set Z_k.
  /// Throws InputError (and leaves the filter unchanged) if a measurement or the control is not finite.
  void step(const Control& u, const MeasurementSet& Z) {
    Stopwatch watch;
    const int k = step_ + 1;
    if (!u.allFinite()) throw InputError("control input", "time step " + std::to_string(k) + ": not finite");
    updater_.validate(Z, k);
    const std::size_t n = particles_.size();
    next_.resize(n);
    stats_.resize(n);
    const bool optimal = config_.proposal == "optimal";
    const bool mh = config_.proposal == "mh";
    const bool paper = config_.weighting == "paper";
    if (mh) mh_.build(particles_, u, Z);
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
    parallel_for(n, [&](std::size_t i) {
      RandomStream rng(config_.seed, (static_cast<std::uint64_t>(k) << 24) + i);
      const Particle& p = particles_[i];
      const State& x_prev = p.trajectory->pose;
      State x;
      State x_estimate;
      double log_increment = 0.0;
      if (mh) {  // the parent's MH-ID (shared by its resampled copies)
        log_increment = mh_.sample(i, rng, x, x_estimate);
      } else if (optimal) {
        thread_local typename OptimalProposal<Motion, Meas>::Result q;
        const State x_pred = motion_.predict(x_prev, u);
        const Covariance P_pred = motion_.process_noise(x_prev, u);
        proposal_.build(*p.map, x_pred, P_pred, Z, rng, q);
        x = proposal_.sample(q, rng);
        x_estimate = q.mean;
        if (paper) {
          log_increment = q.log_marginal;
        } else {
          log_increment = log_gaussian(Motion::local(x, x_pred), P_pred) - proposal_.log_density(q, x);
        }
      } else {
        x = motion_.sample(x_prev, u, rng);
        x_estimate = x;
      }
      std::shared_ptr<Map> map = std::move(fresh_[i]);
      const GlmbUpdateStats s = updater_.update(*p.map, x, Z, k, rng, *map);
      if (!optimal || !paper) log_increment += factorized_ ? s.log_normalizer_factorized : s.log_normalizer;
      Particle& out = next_[i];
      out.log_weight = p.log_weight + log_increment;
      if (!std::isfinite(out.log_weight)) out.log_weight = kLogZero;
      out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
      out.map = std::move(map);
      stats_[i] = s;
    });
    // normalise
    log_w_.resize(n);
    for (std::size_t i = 0; i < n; ++i) log_w_[i] = next_[i].log_weight;
    if (log_sum_exp(log_w_) == kLogZero) std::fill(log_w_.begin(), log_w_.end(), 0.0);  // all failed: uniform
    normalize_log_weights(log_w_);
    for (std::size_t i = 0; i < n; ++i) next_[i].log_weight = log_w_[i];
    StepReport report;
    report.step = k;
    report.ess = effective_sample_size(log_w_);
    const std::size_t best =
        static_cast<std::size_t>(std::max_element(log_w_.begin(), log_w_.end()) - log_w_.begin());
    report.best_particle = static_cast<int>(best);
    report.hypotheses = stats_[best].hypotheses;
    report.tracks = stats_[best].tracks;
    report.active_tracks = stats_[best].active_tracks;
    report.log_likelihood = stats_[best].log_normalizer;
    best_ = next_[best];
    weighted_mean_ = weighted_mean(next_);
    retired_.clear();
    for (const auto& p : particles_) retired_.push_back(p.map);
    particles_.swap(next_);
    // resample
    const bool resample =
        config_.resampling == "always" || report.ess < config_.ess_threshold * static_cast<double>(n);
    if (resample && n > 1) {
      RandomStream rng(config_.seed, (static_cast<std::uint64_t>(k) << 24) + 0xFFFFFFULL);
      resample_particles(particles_, next_, log_w_, rng);
      ++resample_count_;
    }
    for (auto& p : next_) p = Particle{};  // release references held by the scratch copies
    // the previous maps no particle uses any more go to the pool (each once; the const_pointer_cast is
    // sound: every map here was created non-const by this class)
    std::sort(retired_.begin(), retired_.end(),
              [](const auto& a, const auto& b) { return std::less<const Map*>()(a.get(), b.get()); });
    retired_.erase(std::unique(retired_.begin(), retired_.end()), retired_.end());
    for (auto& m : retired_)
      if (m.use_count() == 1) pool_.push_back(std::const_pointer_cast<Map>(std::move(m)));
    retired_.clear();
    report.resampled = resample && n > 1;
    step_ = k;
    report.ms = watch.elapsed_ms();
    last_ = report;
  }

  // ----- estimates (taken from the highest-weight particle before resampling) -----
  /// The estimated pose at the last step (highest-weight particle).
  const State& pose() const { return best_.trajectory->pose; }
  /// The weighted mean pose at the last step (mean in the tangent space at the best pose).
  const State& mean_pose() const { return step_ == 0 ? best_.trajectory->pose : weighted_mean_; }
  /// The highest-weight particle's trajectory, steps 0..k.
  PoseList trajectory() const { return best_.trajectory->poses(); }
  /// The highest-weight particle's Rao–Blackwellised estimates, steps 0..k: at each step the mean of the
  /// optimal-kernel proposal given that particle's history and map (its sampled pose for the prior proposal).
  /// Free of the sampling noise of trajectory(), which the particle's map is conditioned on.
  PoseList estimated_trajectory() const { return best_.trajectory->estimates(); }
  /// The highest-weight particle's map estimate (MAP cardinality, then its best hypothesis).
  LandmarkList landmarks() const { return estimate_map(*best_.map); }
  /// The highest-weight particle's map (all hypotheses).
  const Map& map() const { return *best_.map; }

  const StepReport& last_report() const { return last_; }
  int steps() const { return step_; }
  int resample_count() const { return resample_count_; }
  const std::vector<Particle>& particles() const { return particles_; }
  const RbpfConfig& config() const { return config_; }

 private:
  State weighted_mean(const std::vector<Particle>& ps) const {
    const State& ref = best_.trajectory->pose;
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
  bool factorized_ = false;       ///< RbpfConfig::particle_normalizer == "factorized"
  std::vector<Particle> particles_, next_;
  std::vector<std::shared_ptr<Map>> fresh_, pool_;   ///< posterior maps of this step; recyclable maps
  std::vector<std::shared_ptr<const Map>> retired_;  ///< the previous step's maps, checked for reuse
  std::vector<GlmbUpdateStats> stats_;
  std::vector<double> log_w_;
  Particle best_;
  State weighted_mean_;
  StepReport last_;
  int step_ = 0;
  int resample_count_ = 0;
};

}  // namespace glmbslam::backend
