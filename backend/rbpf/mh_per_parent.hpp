#pragma once
// The multi-hypothesis importance density computed once per parent (paper 003's reference implementation):
// particles that are resampled copies of one parent (same trajectory node) share one MH-ID. The build draws
// no random numbers, so sharing it is exact. Used by GlmbSlam and PhdSlam with proposal "mh".
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "backend/rbpf/mh_proposal.hpp"
#include "core/gaussian.hpp"
#include "core/parallel.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

template <class Motion, class Meas>
class MhPerParent {
 public:
  using State = typename Motion::State;
  using Control = typename Motion::Control;
  using Covariance = typename Motion::Covariance;
  using MeasurementSet = typename MhProposal<Motion, Meas>::MeasurementSet;

  MhPerParent(const Motion& motion, const Meas& model, const MhProposalConfig& config)
      : motion_(motion), proposal_(motion, model, config), single_mean_(config.single_particle == "mean") {}

  /// One MH-ID per distinct parent of `particles` (each with `trajectory` and `map`), built in parallel at
  /// x̄ = f(x⁻, u), P̄ = the process noise.
  template <class Particle>
  void build(const std::vector<Particle>& particles, const Control& u, const MeasurementSet& Z) {
    const std::size_t n = particles.size();
    use_mean_ = single_mean_ && n == 1;
    parent_of_.resize(n);
    parents_.clear();
    parent_slot_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const auto [it, inserted] =
          parent_slot_.emplace(particles[i].trajectory.get(), static_cast<int>(parents_.size()));
      if (inserted) parents_.push_back(i);
      parent_of_[i] = it->second;
    }
    const std::size_t np = parents_.size();
    if (results_.size() < np) results_.resize(np);
    pred_.resize(np);
    pred_cov_.resize(np);
    parallel_for(np, [&](std::size_t s) {
      const Particle& par = particles[parents_[s]];
      const State& x_prev = par.trajectory->pose;
      pred_[s] = motion_.predict(x_prev, u);
      pred_cov_[s] = motion_.process_noise(x_prev, u);
      RandomStream unused(0, 0);  // the build draws nothing
      proposal_.build(*par.map, pred_[s], pred_cov_[s], Z, unused, results_[s]);
    });
  }

  /// Particle i: x ~ its parent's MH-ID, x_estimate = the MH-ID's mean; returns log f(x|x⁻,u) − log q(x)
  /// with the full mixture density q (Eq. 45). With a single particle and MhProposalConfig::single_particle
  /// "mean", x = x_estimate (no draw; the weight of a single particle is normalised away).
  double sample(std::size_t i, RandomStream& rng, State& x, State& x_estimate) const {
    const std::size_t s = static_cast<std::size_t>(parent_of_[i]);
    const auto& q = results_[s];
    x_estimate = proposal_.mean(q);
    x = use_mean_ ? x_estimate : proposal_.sample(q, rng);
    return log_gaussian(Motion::local(x, pred_[s]), pred_cov_[s]) - proposal_.log_density(q, x);
  }

 private:
  Motion motion_;
  MhProposal<Motion, Meas> proposal_;
  bool single_mean_ = false;  ///< MhProposalConfig::single_particle == "mean"
  bool use_mean_ = false;     ///< ... and this step has one particle
  std::vector<int> parent_of_;
  std::vector<std::size_t> parents_;
  std::unordered_map<const void*, int> parent_slot_;
  std::vector<typename MhProposal<Motion, Meas>::Result> results_;
  std::vector<State, Eigen::aligned_allocator<State>> pred_;
  std::vector<Covariance, Eigen::aligned_allocator<Covariance>> pred_cov_;
};

}  // namespace glmbslam::backend
