#pragma once
// LMB-SLAM: a Rao–Blackwellised particle filter whose particles each carry a trajectory and a labelled
// multi-Bernoulli landmark map (lmb_map.hpp), updated by the δ-GLMB joint prediction/update followed by the
// LMB approximation every step (lmb_update.hpp) — the LMB-SLAM filter paper 000 compares against — with
// the proposals of δ-GLMB-SLAM:
//   proposal "prior":   x ~ f(·|x⁻, u)
//   proposal "optimal": x ~ the optimal-kernel Gaussian of δ-GLMB-SLAM 2.0
//   (backend/rbpf/optimal_proposal.hpp)
//                       built on the LMB's most probable label set (the Bernoullis with r ≥ 0.5, each at its
//                       highest-weight component: the LMB's highest-weight δ-GLMB hypothesis) and its births
//   weight "importance": log w += log Ĝ(x) + log f(x|x⁻,u) − log q(x);  "paper": Eq. 33 as printed
// (RbpfConfig: proposal, weighting, resampling, particle_normalizer, single_particle and the δ-GLMB update
// settings in RbpfConfig::glmb; "mh" is not supported). The particle loop is the shared skeleton of
// backend/rbpf/particle_set.hpp; the estimate is the highest-weight particle before resampling and its
// Bernoullis with existence above LmbConfig::estimate_existence.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend/glmb/glmb_map.hpp"
#include "backend/lmb/lmb_config.hpp"
#include "backend/lmb/lmb_map.hpp"
#include "backend/lmb/lmb_update.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "backend/rbpf/particle_set.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "core/error.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::backend {

struct LmbStepReport {
  int step = 0;
  double ess = 0.0;  ///< 1/Σw² after the weight update (before resampling)
  bool resampled = false;
  double ms = 0.0;
  int best_particle = 0;
  int tracks = 0;         ///< Bernoullis of the best particle
  int active_tracks = 0;  ///< in view of the best particle
  int solutions = 0;      ///< distinct association maps of the best particle's update
  double log_likelihood = 0.0;
};

template <class Motion, class Meas>
class LmbSlam {
 public:
  using State = typename Motion::State;
  using Control = typename Motion::Control;
  using Tangent = typename Motion::Tangent;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = LmbMap<Meas>;
  using Node = TrajectoryNode<State>;
  using PoseList = std::vector<State, Eigen::aligned_allocator<State>>;
  using LandmarkList = std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>>;
  using Particle = RbpfParticle<State, Map>;

  /// Throws ConfigError on an invalid config.
  LmbSlam(const Motion& motion, const Meas& model, const RbpfConfig& config, const LmbConfig& lmb,
          const State& initial_pose)
      : motion_(motion),
        model_(model),
        config_(validated(config)),
        lmb_(lmb),
        updater_(model, config.glmb, lmb),
        proposal_(motion, model, config),
        factorized_(config.particle_normalizer == "factorized"),
        set_(config.particles, config.seed,
             ResamplingPolicy::parse(config.resampling, config.ess_threshold, "rbpf.resampling"),
             initial_pose, std::make_shared<const Map>()) {
    validate_lmb_config(lmb);
  }

  /// Optional, before the first step: Z_0 at the (known) initial pose becomes the birth candidates of step 1.
  void initial_scan(const MeasurementSet& Z) {
    if (set_.steps() != 0)
      throw std::logic_error("LmbSlam::initial_scan must be called before the first step");
    updater_.validate(Z, 0);
    RandomStream rng(config_.seed, 0xFFFFFFULL);
    auto map = std::make_shared<Map>();
    const Particle& p0 = set_.particles()[0];
    updater_.update(*p0.map, p0.trajectory->pose, Z, 0, rng, *map);
    set_.set_common_map(std::move(map));
  }

  /// One filter step with control u (from step k−1 to k) and the measurement set Z_k.
  /// Throws InputError (and leaves the filter unchanged) if a measurement or the control is not finite.
  void step(const Control& u, const MeasurementSet& Z) {
    Stopwatch watch;
    const int k = set_.steps() + 1;
    if (!u.allFinite()) throw InputError("control input", "time step " + std::to_string(k) + ": not finite");
    updater_.validate(Z, k);
    stats_.resize(set_.particles().size());
    const bool optimal = config_.proposal == "optimal";
    const bool paper = config_.weighting == "paper";
    const ParticleStepResult r =
        set_.step([&](std::size_t i, RandomStream& rng, const Particle& p, Particle& out) {
          const State& x_prev = p.trajectory->pose;
          State x, x_estimate;
          double log_increment = 0.0;
          if (optimal) {
            thread_local typename OptimalProposal<Motion, Meas>::Result q;
            thread_local GlmbMap<Meas> view;
            const State x_pred = motion_.predict(x_prev, u);
            const Covariance P_pred = motion_.process_noise(x_prev, u);
            most_probable_hypothesis(*p.map, view);
            proposal_.build(view, x_pred, P_pred, Z, rng, q);
            x = proposal_.sample(q, rng);
            x_estimate = q.mean;
            log_increment =
                paper ? q.log_marginal
                      : log_gaussian(Motion::local(x, x_pred), P_pred) - proposal_.log_density(q, x);
          } else {
            x = motion_.sample(x_prev, u, rng);
            x_estimate = x;
          }
          auto map = std::make_shared<Map>();
          const LmbUpdateStats s = updater_.update(*p.map, x, Z, k, rng, *map);
          if (!optimal || !paper)
            log_increment += factorized_ ? s.log_normalizer_factorized : s.log_normalizer;
          out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
          out.map = std::move(map);
          stats_[i] = s;
          return log_increment;
        });
    LmbStepReport report;
    report.step = k;
    report.ess = r.ess;
    report.best_particle = static_cast<int>(r.best);
    report.resampled = r.resampled;
    report.tracks = stats_[r.best].tracks;
    report.active_tracks = stats_[r.best].active_tracks;
    report.solutions = stats_[r.best].solutions;
    report.log_likelihood = stats_[r.best].log_normalizer;
    report.ms = watch.elapsed_ms();
    last_ = report;
  }

  const State& pose() const { return set_.pose(); }
  PoseList trajectory() const { return set_.trajectory(); }
  /// The highest-weight particle's proposal means (its sampled poses for the prior proposal), steps 0..k.
  PoseList estimated_trajectory() const { return set_.estimated_trajectory(); }
  /// The highest-weight particle's Bernoullis with existence above LmbConfig::estimate_existence.
  LandmarkList landmarks() const { return estimate_lmb_map(*set_.best().map, lmb_.estimate_existence); }
  const Map& map() const { return *set_.best().map; }
  const LmbStepReport& last_report() const { return last_; }
  int steps() const { return set_.steps(); }
  int resample_count() const { return set_.resample_count(); }
  const std::vector<Particle>& particles() const { return set_.particles(); }
  const RbpfConfig& config() const { return config_; }

 private:
  static const RbpfConfig& validated(const RbpfConfig& config) {
    if (config.proposal != "prior" && config.proposal != "optimal")
      throw ConfigError("rbpf.proposal must be 'prior' or 'optimal' for LMB-SLAM");
    if (config.weighting != "importance" && config.weighting != "paper")
      throw ConfigError("rbpf.weighting must be 'importance' or 'paper'");
    if (config.particle_normalizer != "sampled" && config.particle_normalizer != "factorized")
      throw ConfigError("rbpf.particle_normalizer must be 'sampled' or 'factorized'");
    if (config.single_particle != "sample" && config.single_particle != "mean")
      throw ConfigError("rbpf.single_particle must be 'sample' or 'mean'");
    return config;
  }

  /// The LMB's most probable label set as a one-hypothesis δ-GLMB map (what the optimal proposal reads).
  static void most_probable_hypothesis(const Map& lmb, GlmbMap<Meas>& view) {
    view.tracks.clear();
    view.hypotheses.resize(1);
    Hypothesis& h = view.hypotheses[0];
    h.log_weight = 0.0;
    h.tracks.clear();
    for (std::size_t t = 0; t < lmb.tracks.size(); ++t) {
      if (lmb.tracks[t].existence < 0.5) continue;
      const LmbComponent<Meas>& c = lmb.dominant(t);
      h.tracks.push_back(static_cast<std::uint32_t>(view.tracks.size()));
      view.tracks.push_back(Track<Meas>{lmb.tracks[t].label, c.mean, c.cov, lmb.tracks[t].appearance});
    }
    view.births.assign(lmb.births.begin(), lmb.births.end());
  }

  Motion motion_;
  Meas model_;
  RbpfConfig config_;
  LmbConfig lmb_;
  LmbUpdater<Meas> updater_;
  OptimalProposal<Motion, Meas> proposal_;
  bool factorized_ = false;
  ParticleSet<State, Map> set_;
  std::vector<LmbUpdateStats> stats_;
  LmbStepReport last_;
};

}  // namespace glmbslam::backend
