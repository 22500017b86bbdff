#pragma once
// The particle-step skeleton shared by every Rao–Blackwellised SLAM filter of the backend (δ-GLMB-SLAM,
// PHD-SLAM, LMB-SLAM, FastSLAM 2.0): particles of (log weight, trajectory node, map), one step =
//   for every particle i in parallel, with its own RandomStream(seed, (k << 24) + i) (so the output does not
//   depend on the thread count): the filter's propagate(i, rng, particle, out) draws the pose, builds the
//   posterior map and returns the log weight increment; log w_i += increment (−∞ if not finite);
//   normalisation (all −∞: uniform), ESS = 1/Σw², the highest-weight particle (the estimate, taken before
//   resampling), the filter's hook on the weighted set, and systematic resampling every step ("always") or
//   when ESS < ess_threshold·N ("ess") from RandomStream(seed, (k << 24) + 0xFFFFFF).
// The map type is opaque: maps are shared between particles through shared_ptr<const Map>, so resampling
// copies pointers. The filter keeps its own model, proposal and report.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backend/rbpf/resampling.hpp"
#include "backend/rbpf/trajectory.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/parallel.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

/// One particle: normalised log weight, trajectory (parent-linked) and map (shared, immutable).
template <class State, class MapT>
struct RbpfParticle {
  double log_weight = 0.0;
  std::shared_ptr<const TrajectoryNode<State>> trajectory;
  std::shared_ptr<const MapT> map;
};

/// How particles are resampled: "always" or "ess" (ESS below ess_threshold·N).
struct ResamplingPolicy {
  bool always = true;
  double ess_threshold = 0.5;
  /// Throws ConfigError naming `key` unless `mode` is "always" or "ess".
  static ResamplingPolicy parse(const std::string& mode, double ess_threshold, const std::string& key) {
    if (mode != "always" && mode != "ess") throw ConfigError(key + " must be 'always' or 'ess'");
    return ResamplingPolicy{mode == "always", ess_threshold};
  }
};

/// The outcome of one ParticleSet::step.
struct ParticleStepResult {
  int step = 0;
  double ess = 0.0;      ///< 1/Σw² after the weight update (before resampling)
  std::size_t best = 0;  ///< index of the highest-weight particle (before resampling)
  bool resampled = false;
};

template <class State, class MapT>
class ParticleSet {
 public:
  using Particle = RbpfParticle<State, MapT>;
  using Node = TrajectoryNode<State>;
  using PoseList = std::vector<State, Eigen::aligned_allocator<State>>;

  /// N particles of weight 1/N at the initial pose with the common initial map. Throws ConfigError if N < 1.
  ParticleSet(int particles, std::uint64_t seed, const ResamplingPolicy& policy, const State& initial_pose,
              std::shared_ptr<const MapT> initial_map)
      : seed_(seed), policy_(policy) {
    if (particles < 1) throw ConfigError("the particle count must be at least 1");
    auto root = std::make_shared<const Node>(initial_pose, 0, nullptr);
    const double log_w = -std::log(static_cast<double>(particles));
    particles_.assign(static_cast<std::size_t>(particles), Particle{log_w, root, std::move(initial_map)});
    best_ = particles_[0];
  }

  /// Replaces every particle's map by `map` (e.g. after the initial scan at the known pose).
  void set_common_map(std::shared_ptr<const MapT> map) {
    for (auto& p : particles_) p.map = map;
    best_ = particles_[0];
  }

  /// One step k = steps() + 1. `propagate(i, rng, const Particle& in, Particle& out) -> double` sets
  /// out.trajectory and out.map and returns the log weight increment; `on_weighted(next, result)` sees the
  /// normalised particles before the swap and resampling.
  template <class Propagate, class OnWeighted>
  ParticleStepResult step(Propagate&& propagate, OnWeighted&& on_weighted) {
    return step(
        std::forward<Propagate>(propagate), [](std::vector<Particle>&) {},
        std::forward<OnWeighted>(on_weighted));
  }
  /// As above; `adjust(next)` may change the new particles' (unnormalised) log weights after every particle
  /// was propagated (e.g. to pool an estimate over the children of one parent, next[i].trajectory->parent).
  template <class Propagate, class Adjust, class OnWeighted>
  ParticleStepResult step(Propagate&& propagate, Adjust&& adjust, OnWeighted&& on_weighted) {
    const int k = step_ + 1;
    const std::size_t n = particles_.size();
    next_.resize(n);
    parallel_for(n, [&](std::size_t i) {
      RandomStream rng(seed_, (static_cast<std::uint64_t>(k) << 24) + i);
      const Particle& p = particles_[i];
      Particle& out = next_[i];
      const double log_increment = propagate(i, rng, p, out);
      out.log_weight = p.log_weight + log_increment;
      if (!std::isfinite(out.log_weight)) out.log_weight = kLogZero;
    });
    adjust(next_);
    log_w_.resize(n);
    for (std::size_t i = 0; i < n; ++i) log_w_[i] = next_[i].log_weight;
    if (log_sum_exp(log_w_) == kLogZero) std::fill(log_w_.begin(), log_w_.end(), 0.0);  // all failed: uniform
    normalize_log_weights(log_w_);
    for (std::size_t i = 0; i < n; ++i) next_[i].log_weight = log_w_[i];
    ParticleStepResult result;
    result.step = k;
    result.ess = effective_sample_size(log_w_);
    result.best = static_cast<std::size_t>(std::max_element(log_w_.begin(), log_w_.end()) - log_w_.begin());
    best_ = next_[result.best];
    on_weighted(static_cast<const std::vector<Particle>&>(next_), result);
    particles_.swap(next_);
    const bool resample = policy_.always || result.ess < policy_.ess_threshold * static_cast<double>(n);
    if (resample && n > 1) {
      RandomStream rng(seed_, (static_cast<std::uint64_t>(k) << 24) + 0xFFFFFFULL);
      resample_particles(particles_, next_, log_w_, rng);
      ++resample_count_;
    }
    for (auto& p : next_) p = Particle{};  // release references held by the scratch copies
    result.resampled = resample && n > 1;
    step_ = k;
    return result;
  }
  template <class Propagate>
  ParticleStepResult step(Propagate&& propagate) {
    return step(std::forward<Propagate>(propagate),
                [](const std::vector<Particle>&, const ParticleStepResult&) {});
  }

  /// The highest-weight particle of the last step (before resampling); particle 0 before the first step.
  const Particle& best() const { return best_; }
  const std::vector<Particle>& particles() const { return particles_; }
  int steps() const { return step_; }
  int resample_count() const { return resample_count_; }
  std::uint64_t seed() const { return seed_; }
  /// The estimated pose (highest-weight particle) at the last step.
  const State& pose() const { return best_.trajectory->pose; }
  /// The highest-weight particle's trajectory, steps 0..k.
  PoseList trajectory() const { return best_.trajectory->poses(); }
  /// Its point estimates (the proposal means), steps 0..k.
  PoseList estimated_trajectory() const { return best_.trajectory->estimates(); }

 private:
  std::uint64_t seed_ = 0;
  ResamplingPolicy policy_;
  std::vector<Particle> particles_, next_;
  std::vector<double> log_w_;
  Particle best_;
  int step_ = 0;
  int resample_count_ = 0;
};

}  // namespace glmbslam::backend
