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
#include <memory>
#include <string>
#include <vector>

#include "backend/glmb/glmb_map.hpp"
#include "backend/lmb/lmb_config.hpp"
#include "backend/lmb/lmb_map.hpp"
#include "backend/lmb/lmb_update.hpp"
#include "backend/rbpf/labelled_map_filter.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "backend/rbpf/particle_set.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "core/error.hpp"
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
        weighting_(config),
        set_(config.particles, config.seed,
             ResamplingPolicy::parse(config.resampling, config.ess_threshold, "rbpf.resampling"),
             initial_pose, std::make_shared<const Map>()) {
    validate_lmb_config(lmb);
  }

  /// Optional, before the first step: Z_0 at the (known) initial pose becomes the birth candidates of step 1.
  void initial_scan(const MeasurementSet& Z) {
    backend::initial_scan(set_, updater_, Z, config_.seed, "LmbSlam");
  }

  /// One filter step with control u (from step k−1 to k) and the measurement set Z_k.
  /// Throws InputError (and leaves the filter unchanged) if a measurement or the control is not finite.
  void step(const Control& u, const MeasurementSet& Z) {
    Stopwatch watch;
    const int k = begin_step(set_, updater_, u, Z);
    const std::size_t n = set_.particles().size();
    stats_.resize(n);
    map_log_.resize(n);
    const ParticleStepResult r = set_.step(
        [&](std::size_t i, RandomStream& rng, const Particle& p, Particle& out) {
          State x, x_estimate;
          auto view = [&]() -> const GlmbMap<Meas>& {  // the optimal kernel reads the most probable label set
            thread_local GlmbMap<Meas> v;
            most_probable_hypothesis(*p.map, v);
            return v;
          };
          double log_increment =
              draw_pose(weighting_, motion_, proposal_, view, p.trajectory->pose, u, Z, rng, x, x_estimate);
          auto map = std::make_shared<Map>();
          const LmbUpdateStats s = updater_.update(*p.map, x, Z, k, rng, *map);
          map_log_[i] = weighting_.map_factor(s);
          log_increment += map_log_[i];
          out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
          out.map = std::move(map);
          stats_[i] = s;
          return log_increment;
        },
        [&](std::vector<Particle>& next) {
          if (weighting_.sibling_mean) pool_sibling_normalizers(map_log_, next, pool_scratch_);
        },
        [](const std::vector<Particle>&, const ParticleStepResult&) {});
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

  /// A step (k−1 → k, control u) whose sensor saw nothing: the poses move, the maps stay (blind_step in
  /// backend/rbpf/labelled_map_filter.hpp). Throws InputError (and leaves the filter unchanged) if u is not
  /// finite.
  void blind_step(const Control& u) {
    Stopwatch watch;
    const ParticleStepResult r = backend::blind_step(set_, motion_, u);
    record_blind_step(last_, r, watch.elapsed_ms());
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
    validate_rbpf_weighting(config);
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
  ProposalWeighting weighting_;
  std::vector<double> map_log_;  ///< this step's child i: its map factor log Ĝ (sibling_mean)
  std::vector<double> pool_scratch_;
  ParticleSet<State, Map> set_;
  std::vector<LmbUpdateStats> stats_;
  LmbStepReport last_;
};

}  // namespace glmbslam::backend
