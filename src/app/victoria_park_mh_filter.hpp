#pragma once
// δ-GLMB-SLAM with the multi-hypothesis importance density (backend/rbpf/mh_proposal.hpp): the particle
// filter of GlmbSlam (same δ-GLMB map update, importance weighting, systematic resampling, shared
// trajectories/maps, per-(seed, step, particle) random streams) with the MH-ID as proposal, computed ONCE PER
// PARENT: particles that are resampled copies of one parent (same trajectory node) share one MH-ID, as in
// paper 003's reference implementation. The MH-ID build is deterministic, so sharing it is exact.
//
// Per step k: for every distinct parent: x̄ = f(x⁻, u), P̄ = process noise, q = MH-ID(map, x̄, P̄, Z);
// for every particle: x ~ q, δ-GLMB update at x → log Ĝ(x), log w += log Ĝ(x) + log N(x ⊖ x̄; 0, P̄) − log q(x)
// (Eq. 45 with the δ-GLMB normaliser as the measurement term); then normalisation, the estimate (highest
// weight, before resampling) and resampling when ESS < ess_threshold·N ("ess") or every step ("always").
// This class exists so that glmbslam run can use the MH-ID before GlmbSlam gains a proposal "mh"; it reuses
// RbpfConfig (particles, seed, resampling, ess_threshold, glmb).
#include <cmath>
#include <memory>
#include <unordered_map>
#include <vector>

#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/glmb_update.hpp"
#include "backend/rbpf/mh_proposal.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "backend/rbpf/resampling.hpp"
#include "backend/rbpf/trajectory.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/parallel.hpp"
#include "core/random.hpp"

namespace glmbslam::app {

struct MhStepReport {
  double ess = 0.0;
  bool resampled = false;
  int parents = 0;     ///< distinct parents (MH-IDs built)
  int components = 0;  ///< MH-ID components of the best particle's parent
};

template <class Motion, class Meas>
class GlmbMhSlam {
 public:
  using State = typename Motion::State;
  using Control = typename Motion::Control;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = backend::GlmbMap<Meas>;
  using Node = backend::TrajectoryNode<State>;
  using Proposal = backend::MhProposal<Motion, Meas>;
  using LandmarkList =
      std::vector<backend::LandmarkEstimate<Meas>, Eigen::aligned_allocator<backend::LandmarkEstimate<Meas>>>;

  struct Particle {
    double log_weight = 0.0;
    std::shared_ptr<const Node> trajectory;
    std::shared_ptr<const Map> map;
  };

  GlmbMhSlam(const Motion& motion, const Meas& model, const backend::RbpfConfig& config,
             const backend::MhProposalConfig& mh, const State& initial_pose)
      : motion_(motion), config_(config), updater_(model, config.glmb), proposal_(motion, model, mh) {
    if (config.particles < 1) throw ConfigError("rbpf.particles must be at least 1");
    auto root = std::make_shared<const Node>(initial_pose, 0, nullptr);
    auto empty = std::make_shared<const Map>(Map::empty());
    particles_.assign(config.particles,
                      Particle{-std::log(static_cast<double>(config.particles)), root, empty});
    best_ = particles_[0];
  }

  void step(const Control& u, const MeasurementSet& Z) {
    const int k = step_ + 1;
    updater_.validate(Z, k);
    const std::size_t n = particles_.size();
    // distinct parents
    parent_of_.resize(n);
    parents_.clear();
    slot_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const auto [it, inserted] =
          slot_.emplace(particles_[i].trajectory.get(), static_cast<int>(parents_.size()));
      if (inserted) parents_.push_back(i);
      parent_of_[i] = it->second;
    }
    const std::size_t np = parents_.size();
    if (proposals_.size() < np) proposals_.resize(np);
    x_pred_.resize(np);
    P_pred_.resize(np);
    parallel_for(np, [&](std::size_t p) {
      const Particle& par = particles_[parents_[p]];
      const State& x_prev = par.trajectory->pose;
      x_pred_[p] = motion_.predict(x_prev, u);
      P_pred_[p] = motion_.process_noise(x_prev, u);
      RandomStream unused(config_.seed, 0);
      proposal_.build(*par.map, x_pred_[p], P_pred_[p], Z, unused, proposals_[p]);
    });
    next_.resize(n);
    parallel_for(n, [&](std::size_t i) {
      RandomStream rng(config_.seed, (static_cast<std::uint64_t>(k) << 24) + i);
      const Particle& p = particles_[i];
      const int s = parent_of_[i];
      const State x = proposal_.sample(proposals_[s], rng);
      double log_inc =
          log_gaussian(Motion::local(x, x_pred_[s]), P_pred_[s]) - proposal_.log_density(proposals_[s], x);
      auto map = std::make_shared<Map>();
      const backend::GlmbUpdateStats st = updater_.update(*p.map, x, Z, k, rng, *map);
      log_inc += st.log_normalizer;
      Particle& out = next_[i];
      out.log_weight = p.log_weight + log_inc;
      if (!std::isfinite(out.log_weight)) out.log_weight = kLogZero;
      out.trajectory = std::make_shared<const Node>(x, k, p.trajectory);
      out.map = std::move(map);
    });
    log_w_.resize(n);
    for (std::size_t i = 0; i < n; ++i) log_w_[i] = next_[i].log_weight;
    if (log_sum_exp(log_w_) == kLogZero) std::fill(log_w_.begin(), log_w_.end(), 0.0);
    normalize_log_weights(log_w_);
    for (std::size_t i = 0; i < n; ++i) next_[i].log_weight = log_w_[i];
    MhStepReport report;
    report.ess = effective_sample_size(log_w_);
    report.parents = static_cast<int>(np);
    const std::size_t best =
        static_cast<std::size_t>(std::max_element(log_w_.begin(), log_w_.end()) - log_w_.begin());
    report.components = static_cast<int>(proposals_[parent_of_[best]].components.size());
    best_ = next_[best];
    particles_.swap(next_);
    const bool resample =
        config_.resampling == "always" || report.ess < config_.ess_threshold * static_cast<double>(n);
    if (resample && n > 1) {
      RandomStream rng(config_.seed, (static_cast<std::uint64_t>(k) << 24) + 0xFFFFFFULL);
      backend::resample_particles(particles_, next_, log_w_, rng);
      ++resample_count_;
    }
    for (auto& p : next_) p = Particle{};  // release references held by the scratch copies
    report.resampled = resample && n > 1;
    step_ = k;
    last_ = report;
  }

  const State& pose() const { return best_.trajectory->pose; }
  LandmarkList landmarks() const { return backend::estimate_map(*best_.map); }
  const MhStepReport& last_report() const { return last_; }
  int resample_count() const { return resample_count_; }

 private:
  Motion motion_;
  backend::RbpfConfig config_;
  backend::GlmbUpdater<Meas> updater_;
  Proposal proposal_;
  std::vector<Particle> particles_, next_;
  std::vector<int> parent_of_;
  std::vector<std::size_t> parents_;
  std::unordered_map<const Node*, int> slot_;
  std::vector<typename Proposal::Result> proposals_;
  std::vector<State, Eigen::aligned_allocator<State>> x_pred_;
  std::vector<Covariance, Eigen::aligned_allocator<Covariance>> P_pred_;
  std::vector<double> log_w_;
  Particle best_;
  MhStepReport last_;
  int step_ = 0;
  int resample_count_ = 0;
};

}  // namespace glmbslam::app
