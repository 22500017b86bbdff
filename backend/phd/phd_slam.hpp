#pragma once
// RB-PHD-SLAM 1.0 (Mullane, Vo, Adams & Vo, paper 002; digest 1.5): a Rao–Blackwellised particle filter whose
// particles each carry a trajectory and a GM-PHD landmark map (gm_phd_map.hpp), with the motion-model
// ("prior") proposal, so the weight update is w_k = w_{k−1} · g(Z_k | Z_{1:k−1}, X_{0:k}) (the configured
// likelihood form).
//
// With proposal "mh" (PhdConfig::proposal) it is PHD-SLAM 3.0 (paper 003, digest 2.3–2.5): the pose is drawn
// from the multi-hypothesis importance density (backend/rbpf/mh_proposal.hpp with the GM-PHD landmark adapter
// phd_mh_landmarks.hpp: η = GM weight capped at 1), built once per parent (resampled copies of one parent
// share one build — exact, the build draws no random numbers), and the weight is Eq. 45:
//   log w += log g(Z_k | Z_{1:k−1}, X_{0:k}) + log f(x | x⁻, u) − log Σ_t κ̃^t N(x; μ^t, Σ^t)
// with the configured PHD likelihood g (PhdConfig::likelihood; "poisson" = Eq. 46 + the expected-detections
// term).
//
// Per step k (first call of step() is k = 1), for every particle in parallel with its own RandomStream
// (seed, k, particle) — so the output does not depend on the thread count: x ~ f(·|x⁻, u) (or the MH-ID);
// map update at x; log w += log g (+ the importance ratio). Then normalisation, the estimate (highest-weight
// particle, before resampling) and systematic resampling every step ("always") or when ESS < ess_threshold·N
// ("ess"): the particle-step skeleton of backend/rbpf/particle_set.hpp. Trajectories (parent-linked nodes)
// and maps (shared_ptr to const) are shared between particles, so resampling copies pointers.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "backend/phd/gm_phd_map.hpp"
#include "backend/phd/phd_mh_landmarks.hpp"
#include "backend/rbpf/mh_per_parent.hpp"
#include "backend/rbpf/particle_set.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::backend {

struct PhdStepReport {
  int step = 0;
  double ess = 0.0;  ///< 1/Σw² after the weight update (before resampling)
  bool resampled = false;
  double ms = 0.0;  ///< wall time of step()
  int best_particle = 0;
  int components = 0;  ///< GM components of the best particle
  double log_likelihood = 0.0;
};

template <class Motion, class Meas>
class PhdSlam {
 public:
  using State = typename Motion::State;
  using Control = typename Motion::Control;
  using Tangent = typename Motion::Tangent;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = GmPhdMap<Meas>;
  using Component = GmPhdComponent<Meas>;
  using ComponentList = std::vector<Component, Eigen::aligned_allocator<Component>>;
  using Node = TrajectoryNode<State>;
  using PoseList = std::vector<State, Eigen::aligned_allocator<State>>;
  using Particle = RbpfParticle<State, Map>;

  /// Throws ConfigError on an invalid config. `mh` configures proposal "mh" (ignored otherwise).
  PhdSlam(const Motion& motion, const Meas& model, const PhdConfig& config, const State& initial_pose,
          const MhProposalConfig& mh = MhProposalConfig())
      : motion_(motion),
        config_(config),
        updater_(model, config),
        mh_(motion, model, mh),
        set_(config.particles, config.seed,
             ResamplingPolicy{config.resampling == "always", config.ess_threshold}, initial_pose,
             std::make_shared<const Map>()) {}

  /// Optional, before the first step: the measurement set Z_0 taken at the (known) initial pose. It updates
  /// the common initial map (so its measurements become birth components for step 1), anchoring the map to
  /// the initial pose. Throws InputError on a non-finite measurement, std::logic_error after step().
  void initial_scan(const MeasurementSet& Z) {
    if (set_.steps() != 0)
      throw std::logic_error("PhdSlam::initial_scan must be called before the first step");
    updater_.validate(Z, 0);
    auto map = std::make_shared<Map>();
    const Particle& p0 = set_.particles()[0];
    updater_.update(*p0.map, p0.trajectory->pose, Z, *map);
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
    const bool mh = config_.proposal == "mh";
    if (mh) mh_.build(set_.particles(), u, Z);
    const ParticleStepResult r =
        set_.step([&](std::size_t i, RandomStream& rng, const Particle& p, Particle& out) {
          State x, x_estimate;
          double log_ratio = 0.0;  // log f(x|x⁻,u) − log q(x) (0 for the prior proposal)
          if (mh) {                // the parent's MH-ID (shared by its resampled copies)
            log_ratio = mh_.sample(i, rng, x, x_estimate);
          } else {
            x = motion_.sample(p.trajectory->pose, u, rng);
            x_estimate = x;
          }
          auto map = std::make_shared<Map>();
          const GmPhdUpdateStats s = updater_.update(*p.map, x, Z, *map);
          out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
          out.map = std::move(map);
          stats_[i] = s;
          return s.log_likelihood + log_ratio;
        });
    PhdStepReport report;
    report.step = k;
    report.ess = r.ess;
    report.best_particle = static_cast<int>(r.best);
    report.components = stats_[r.best].components;
    report.log_likelihood = stats_[r.best].log_likelihood;
    report.resampled = r.resampled;
    report.ms = watch.elapsed_ms();
    last_ = report;
  }

  /// The estimated pose at the last step (highest-weight particle, before resampling).
  const State& pose() const { return set_.pose(); }
  /// The highest-weight particle's trajectory, steps 0..k.
  PoseList trajectory() const { return set_.trajectory(); }
  /// Its proposal means, steps 0..k (the MH-ID mixture mean for "mh", the sampled pose for "prior").
  PoseList estimated_trajectory() const { return set_.estimated_trajectory(); }
  /// The highest-weight particle's map estimate: components with weight > existence_threshold.
  ComponentList landmarks() const { return updater_.estimate(*set_.best().map); }
  const Map& map() const { return *set_.best().map; }
  const PhdStepReport& last_report() const { return last_; }
  int steps() const { return set_.steps(); }
  int resample_count() const { return set_.resample_count(); }
  const std::vector<Particle>& particles() const { return set_.particles(); }
  const PhdConfig& config() const { return config_; }

 private:
  Motion motion_;
  PhdConfig config_;
  GmPhdUpdater<Meas> updater_;
  MhPerParent<Motion, Meas> mh_;  ///< proposal "mh"
  ParticleSet<State, Map> set_;
  std::vector<GmPhdUpdateStats> stats_;
  PhdStepReport last_;
};

}  // namespace glmbslam::backend
