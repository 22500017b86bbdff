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
// ("ess"). Trajectories (parent-linked nodes) and maps (shared_ptr to const) are shared between particles, so
// resampling copies pointers.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "backend/phd/gm_phd_map.hpp"
#include "backend/phd/phd_mh_landmarks.hpp"
#include "backend/rbpf/mh_per_parent.hpp"
#include "backend/rbpf/resampling.hpp"
#include "backend/rbpf/trajectory.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/parallel.hpp"
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

  struct Particle {
    double log_weight = 0.0;  ///< normalised
    std::shared_ptr<const Node> trajectory;
    std::shared_ptr<const Map> map;
  };

  /// Throws ConfigError on an invalid config. `mh` configures proposal "mh" (ignored otherwise).
  PhdSlam(const Motion& motion, const Meas& model, const PhdConfig& config, const State& initial_pose,
          const MhProposalConfig& mh = MhProposalConfig())
      : motion_(motion), config_(config), updater_(model, config), mh_(motion, model, mh) {
    auto root = std::make_shared<const Node>(initial_pose, 0, nullptr);
    auto empty = std::make_shared<const Map>();
    const double log_w = -std::log(static_cast<double>(config.particles));
    particles_.assign(static_cast<std::size_t>(config.particles), Particle{log_w, root, empty});
    best_ = particles_[0];
  }

  /// Optional, before the first step: the measurement set Z_0 taken at the (known) initial pose. It updates
  /// the common initial map (so its measurements become birth components for step 1), anchoring the map to
  /// the initial pose. Throws InputError on a non-finite measurement, std::logic_error after step().
  void initial_scan(const MeasurementSet& Z) {
    if (step_ != 0) throw std::logic_error("PhdSlam::initial_scan must be called before the first step");
    updater_.validate(Z, 0);
    auto map = std::make_shared<Map>();
    updater_.update(*particles_[0].map, particles_[0].trajectory->pose, Z, *map);
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
    const bool mh = config_.proposal == "mh";
    if (mh) mh_.build(particles_, u, Z);
    parallel_for(n, [&](std::size_t i) {
      RandomStream rng(config_.seed, (static_cast<std::uint64_t>(k) << 24) + i);
      const Particle& p = particles_[i];
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
      Particle& out = next_[i];
      out.log_weight = p.log_weight + s.log_likelihood + log_ratio;
      if (!std::isfinite(out.log_weight)) out.log_weight = kLogZero;
      out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
      out.map = std::move(map);
      stats_[i] = s;
    });
    log_w_.resize(n);
    for (std::size_t i = 0; i < n; ++i) log_w_[i] = next_[i].log_weight;
    if (log_sum_exp(log_w_) == kLogZero) std::fill(log_w_.begin(), log_w_.end(), 0.0);  // all failed: uniform
    normalize_log_weights(log_w_);
    for (std::size_t i = 0; i < n; ++i) next_[i].log_weight = log_w_[i];
    PhdStepReport report;
    report.step = k;
    report.ess = effective_sample_size(log_w_);
    const auto best =
        static_cast<std::size_t>(std::max_element(log_w_.begin(), log_w_.end()) - log_w_.begin());
    report.best_particle = static_cast<int>(best);
    report.components = stats_[best].components;
    report.log_likelihood = stats_[best].log_likelihood;
    best_ = next_[best];
    particles_.swap(next_);
    const bool resample =
        config_.resampling == "always" || report.ess < config_.ess_threshold * static_cast<double>(n);
    if (resample && n > 1) {
      RandomStream rng(config_.seed, (static_cast<std::uint64_t>(k) << 24) + 0xFFFFFFULL);
      resample_particles(particles_, next_, log_w_, rng);
      ++resample_count_;
    }
    for (auto& p : next_) p = Particle{};  // release references held by the scratch copies
    report.resampled = resample && n > 1;
    step_ = k;
    report.ms = watch.elapsed_ms();
    last_ = report;
  }

  /// The estimated pose at the last step (highest-weight particle, before resampling).
  const State& pose() const { return best_.trajectory->pose; }
  /// The highest-weight particle's trajectory, steps 0..k.
  PoseList trajectory() const { return best_.trajectory->poses(); }
  /// Its proposal means, steps 0..k (the MH-ID mixture mean for "mh", the sampled pose for "prior").
  PoseList estimated_trajectory() const { return best_.trajectory->estimates(); }
  /// The highest-weight particle's map estimate: components with weight > existence_threshold.
  ComponentList landmarks() const { return updater_.estimate(*best_.map); }
  const Map& map() const { return *best_.map; }
  const PhdStepReport& last_report() const { return last_; }
  int steps() const { return step_; }
  int resample_count() const { return resample_count_; }
  const std::vector<Particle>& particles() const { return particles_; }
  const PhdConfig& config() const { return config_; }

 private:
  Motion motion_;
  PhdConfig config_;
  GmPhdUpdater<Meas> updater_;
  MhPerParent<Motion, Meas> mh_;  ///< proposal "mh"
  std::vector<Particle> particles_, next_;
  std::vector<GmPhdUpdateStats> stats_;
  std::vector<double> log_w_;
  Particle best_;
  PhdStepReport last_;
  int step_ = 0;
  int resample_count_ = 0;
};

}  // namespace glmbslam::backend
