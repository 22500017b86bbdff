#pragma once
// What the Rao–Blackwellised filters with a labelled-RFS map per particle — δ-GLMB-SLAM (glmb_slam.hpp) and
// LMB-SLAM (backend/lmb/lmb_slam.hpp) — share around the particle loop of particle_set.hpp:
//  - the checks of the RbpfConfig settings both read (weighting, particle normaliser, single particle);
//  - the initial scan: Z_0 at the known initial pose updates the common initial map, so its measurements
//    become the birth candidates of step 1 and anchor the map to the initial pose;
//  - the step preamble: k = steps + 1, and a non-finite control or measurement leaves the filter unchanged;
//  - the blind step: a frame whose sensor saw nothing moves the poses and leaves the maps as they were;
//  - the pose draw of proposals "prior" (x ~ f(·|x⁻, u), δ-GLMB-SLAM 1.0) and "optimal" (the optimal-kernel
//    Gaussian of δ-GLMB-SLAM 2.0, optimal_proposal.hpp) with its weight factor (paper 000 Eq. 33 as printed
//    for weighting "paper", f/q otherwise), and the map's factor log Ĝ added to it.
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend/glmb/glmb_map.hpp"
#include "backend/rbpf/optimal_proposal.hpp"
#include "backend/rbpf/particle_set.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "core/error.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

/// Throws ConfigError on an invalid weighting, particle_normalizer, single_particle or proposal_scale
/// setting.
inline void validate_rbpf_weighting(const RbpfConfig& config) {
  if (config.weighting != "importance" && config.weighting != "paper")
    throw ConfigError("rbpf.weighting must be 'importance' or 'paper'");
  if (config.particle_normalizer != "sampled" && config.particle_normalizer != "factorized" &&
      config.particle_normalizer != "sibling_mean")
    throw ConfigError("rbpf.particle_normalizer must be 'sampled', 'factorized' or 'sibling_mean'");
  if (config.single_particle != "sample" && config.single_particle != "mean")
    throw ConfigError("rbpf.single_particle must be 'sample' or 'mean'");
  if (!(config.proposal_scale >= 0.0 && config.proposal_scale <= 1.0))
    throw ConfigError("rbpf.proposal_scale must be in [0, 1]");
}

/// The initial scan of `filter` (named in the error): `updater` takes particle 0's map at its (known) pose
/// with Z_0 to the common map of every particle. Throws std::logic_error after the first step, InputError on
/// a non-finite measurement.
template <class State, class Map, class Updater, class MeasurementSet>
void initial_scan(ParticleSet<State, Map>& set, const Updater& updater, const MeasurementSet& Z,
                  std::uint64_t seed, const char* filter) {
  if (set.steps() != 0)
    throw std::logic_error(std::string(filter) + "::initial_scan must be called before the first step");
  updater.validate(Z, 0);
  RandomStream rng(seed, 0xFFFFFFULL);
  auto map = std::make_shared<Map>();
  const auto& p0 = set.particles()[0];
  updater.update(*p0.map, p0.trajectory->pose, Z, 0, rng, *map);
  set.set_common_map(std::move(map));
}

/// The step preamble: returns k = steps + 1. Throws InputError (before anything changes) if the control or a
/// measurement is not finite.
template <class State, class Map, class Updater, class Control, class MeasurementSet>
int begin_step(const ParticleSet<State, Map>& set, const Updater& updater, const Control& u,
               const MeasurementSet& Z) {
  const int k = set.steps() + 1;
  if (!u.allFinite()) throw InputError("control input", "time step " + std::to_string(k) + ": not finite");
  updater.validate(Z, k);
  return k;
}

/// A step whose sensor saw nothing (a covered lens, a dark or unreadable frame): its field of view is empty,
/// and outside the field of view paper 000 has p_D = 0 and p_S = 1 (Eq. 4–9), so the joint prediction/update
/// (Eq. 11–16) leaves every map as it was and every particle's weight factor is 1. Every pose moves by the
/// prediction f(x⁻, u), undrawn: nothing weighs a draw made in the dark, and the next frame's control is
/// relative to the prediction (a stereo VO that re-finds its last reference after the dark measures the
/// motion across it), so a draw would only add noise (rendered 07 with ten black frames, N = 10: filter ATE
/// 0.96 m with draws, 0.09 m without). The maps, and the birth candidates they hold from the last scan, are
/// shared unchanged. Throws InputError (before anything changes) if the control is not finite.
template <class Motion, class State, class Map>
ParticleStepResult blind_step(ParticleSet<State, Map>& set, const Motion& motion,
                              const typename Motion::Control& u) {
  const int k = set.steps() + 1;
  if (!u.allFinite()) throw InputError("control input", "time step " + std::to_string(k) + ": not finite");
  using Particle = typename ParticleSet<State, Map>::Particle;
  return set.step([&](std::size_t, RandomStream&, const Particle& p, Particle& out) {
    const State x = motion.predict(p.trajectory->pose, u);
    out.trajectory = std::make_shared<const TrajectoryNode<State>>(x, x, k, p.trajectory);
    out.map = p.map;
    return 0.0;
  });
}

/// The step report of a blind step `r` that took `ms`: the previous report's map figures (tracks,
/// hypotheses) hold, the measurement likelihood is 1.
template <class Report>
void record_blind_step(Report& report, const ParticleStepResult& r, double ms) {
  report.step = r.step;
  report.ess = r.ess;
  report.best_particle = static_cast<int>(r.best);
  report.resampled = r.resampled;
  report.log_likelihood = 0.0;
  report.ms = ms;
}

/// How a particle's weight is formed (RbpfConfig: proposal, weighting, particle_normalizer).
struct ProposalWeighting {
  bool optimal = false;       ///< proposal "optimal" (else the prior, or a filter's own proposal)
  bool paper = false;         ///< weighting "paper": paper 000 Eq. 33 as printed
  bool factorized = false;    ///< particle_normalizer "factorized"
  bool sibling_mean = false;  ///< particle_normalizer "sibling_mean" (pool_sibling_normalizers)

  explicit ProposalWeighting(const RbpfConfig& config)
      : optimal(config.proposal == "optimal"),
        paper(config.weighting == "paper"),
        factorized(config.particle_normalizer == "factorized"),
        sibling_mean(config.particle_normalizer == "sibling_mean" && !(optimal && paper)) {}

  /// The map's factor of the weight: log Ĝ (sampled or factorised normaliser), except for the optimal
  /// proposal with weighting "paper", whose Eq. 33 already holds it.
  template <class Stats>
  double map_factor(const Stats& s) const {
    if (optimal && paper) return 0.0;
    return factorized ? s.log_normalizer_factorized : s.log_normalizer;
  }
};

/// particle_normalizer "sibling_mean": the children of one parent (next[i].trajectory->parent) share the
/// log-mean-exp of their map factors map_log[i] (the sampled log Ĝ), which replaces each child's own in its
/// log weight. Children with a non-finite weight or factor are left out and unchanged.
template <class Particle>
void pool_sibling_normalizers(const std::vector<double>& map_log, std::vector<Particle>& next,
                              std::vector<double>& scratch) {
  const std::size_t n = next.size();
  auto pooled = [&](std::size_t j) { return std::isfinite(map_log[j]) && next[j].log_weight != kLogZero; };
  auto parent = [&](std::size_t j) { return next[j].trajectory->parent.get(); };
  for (std::size_t i = 0; i < n; ++i) {
    if (!pooled(i)) continue;
    bool first = true;  // the group is handled at its first pooled member
    for (std::size_t j = 0; j < i && first; ++j) first = !(pooled(j) && parent(j) == parent(i));
    if (!first) continue;
    scratch.clear();
    for (std::size_t j = i; j < n; ++j)
      if (pooled(j) && parent(j) == parent(i)) scratch.push_back(map_log[j]);
    const double mean = log_sum_exp(scratch) - std::log(static_cast<double>(scratch.size()));
    for (std::size_t j = i; j < n; ++j)
      if (pooled(j) && parent(j) == parent(i)) next[j].log_weight += mean - map_log[j];
  }
}

/// Draws x (and its point estimate: the proposal mean, or x itself for the prior) from x⁻ = x_prev with
/// control u: the optimal kernel built on the δ-GLMB map `view()` (called only for proposal "optimal") or
/// the motion model. Returns the proposal's log weight factor: log f(x|x⁻,u) − log q(x) ("importance"),
/// log Σ W (Eq. 33, "paper"), 0 for the prior.
template <class Motion, class Meas, class View, class MeasurementSet>
double draw_pose(const ProposalWeighting& w, const Motion& motion,
                 const OptimalProposal<Motion, Meas>& proposal, const View& view,
                 const typename Motion::State& x_prev, const typename Motion::Control& u,
                 const MeasurementSet& Z, RandomStream& rng, typename Motion::State& x,
                 typename Motion::State& x_estimate) {
  if (!w.optimal) {
    x = motion.sample(x_prev, u, rng);
    x_estimate = x;
    return 0.0;
  }
  thread_local typename OptimalProposal<Motion, Meas>::Result q;
  const typename Motion::State x_pred = motion.predict(x_prev, u);
  const typename Motion::Covariance P_pred = motion.process_noise(x_prev, u);
  proposal.build(view(), x_pred, P_pred, Z, rng, q);
  x = proposal.sample(q, rng);
  x_estimate = q.mean;
  if (w.paper) return q.log_marginal;
  return log_gaussian(Motion::local(x, x_pred), P_pred) - proposal.log_density(q, x);
}

}  // namespace glmbslam::backend
