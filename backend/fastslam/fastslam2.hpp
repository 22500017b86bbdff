#pragma once
// FastSLAM 2.0 (Montemerlo, Thrun, Koller & Wegbreit 2003): a Rao–Blackwellised particle filter whose
// particles each carry a trajectory and one EKF per landmark (fastslam_map.hpp). Paper 003 reports it with
// known associations as the reference of every RFS filter (the oracle row).
//
// Per step k, for every particle in parallel (the particle-step skeleton of backend/rbpf/particle_set.hpp):
//  1. x̄ = f(x⁻, u), P̄ = the process noise (tangent of the motion model's ⊕).
//  2. Association of Z_k with the particle's landmarks:
//     "known": the caller's true labels (set_measurement_labels; −1 = clutter, ignored); a label not yet
//              in the map starts a landmark;
//     "ml":    per pair (z_j, landmark n) inside the χ² gate the pose-marginal likelihood
//              N(z_j; h(x̄, m_n), H_x P̄ H_xᵀ + H_m P_n H_mᵀ + R); pairs accepted greedily in order of
//              decreasing likelihood (each z and landmark once) while the likelihood is at least p₀
//              (new_landmark_likelihood); every other z starts a landmark.
//  3. The FastSLAM 2.0 proposal: the associated measurements update (x̄, P̄) one after the other by EKF
//     updates with the landmark's covariance in the innovation (S = H_x P̄ H_xᵀ + H_m P_n H_mᵀ + R,
//     relinearised at the current x̄); x ~ N(x̄, P̄) (the mean with one particle and single_particle "mean").
//  4. Weight: log w += Σ log N(ν; 0, S) over the sequential updates of step 3 (the marginal likelihood of the
//     associated measurements given x⁻, u and the map; it does not depend on the draw) + log p₀ per new
//     landmark ("ml").
//  5. Map at x: EKF update of each associated landmark; new landmarks by the inverse measurement model;
//     ("ml", remove_unconfirmed) a landmark's score gains 1 per detection and loses p_D(x, m) per scan that
//     misses it (negative evidence weighted by the detection probability: a real landmark's score drifts
//     up by p_D² per scan, one created by clutter falls below zero after about 1/p_D scans in view and is
//     removed).
// Estimate: the highest-weight particle (before resampling); its landmarks ("ml": those detected at least
// estimate_min_detections times).
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "backend/fastslam/fastslam_config.hpp"
#include "backend/fastslam/fastslam_map.hpp"
#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/llt_solve.hpp"
#include "backend/rbpf/particle_set.hpp"
#include "core/error.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::backend {

struct FastSlamStepReport {
  int step = 0;
  double ess = 0.0;  ///< 1/Σw² after the weight update (before resampling)
  bool resampled = false;
  double ms = 0.0;
  int best_particle = 0;
  int landmarks = 0;   ///< landmarks of the best particle
  int associated = 0;  ///< measurements of Z_k associated with a mapped landmark (best particle)
  double log_likelihood = 0.0;
};

template <class Motion, class Meas>
class FastSlam2 {
 public:
  using State = typename Motion::State;
  using Control = typename Motion::Control;
  using Tangent = typename Motion::Tangent;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = FastSlamMap<Meas>;
  using LandmarkType = FastSlamLandmark<Meas>;
  using Node = TrajectoryNode<State>;
  using PoseList = std::vector<State, Eigen::aligned_allocator<State>>;
  using LandmarkList = std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>>;
  using Particle = RbpfParticle<State, Map>;

  /// Throws ConfigError on an invalid config.
  FastSlam2(const Motion& motion, const Meas& model, const FastSlamConfig& config, const State& initial_pose)
      : motion_(motion),
        model_(model),
        config_(validated(config)),
        known_(config.association == "known"),
        use_mean_(config.particles == 1 && config.single_particle == "mean"),
        log_p0_(std::log(config.new_landmark_likelihood)),
        set_(config.particles, config.seed,
             ResamplingPolicy::parse(config.resampling, config.ess_threshold, "fastslam.resampling"),
             initial_pose, std::make_shared<const Map>()) {}

  /// "known" association: the true landmark label of each measurement of the next initial_scan() / step()
  /// (−1 = clutter). Throws std::invalid_argument if the size differs from that measurement set's.
  void set_measurement_labels(const std::vector<int>& labels) { labels_ = labels; }

  /// Optional, before the first step: Z_0 at the known initial pose starts the first landmarks.
  void initial_scan(const MeasurementSet& Z) {
    if (set_.steps() != 0)
      throw std::logic_error("FastSlam2::initial_scan must be called before the first step");
    validate(Z, 0);
    const State& x0 = set_.particles()[0].trajectory->pose;
    auto map = std::make_shared<Map>();
    for (std::size_t j = 0; j < Z.size(); ++j) {
      const std::int64_t id = new_landmark_id(static_cast<int>(j), *map);
      if (id >= 0) add_landmark(x0, Z[j], id, *map);
    }
    set_.set_common_map(std::move(map));
  }

  /// One filter step with control u (from step k−1 to k) and the measurement set Z_k.
  /// Throws InputError (and leaves the filter unchanged) if a measurement or the control is not finite, and
  /// std::invalid_argument if "known" association has no label per measurement.
  void step(const Control& u, const MeasurementSet& Z) {
    Stopwatch watch;
    const int k = set_.steps() + 1;
    if (!u.allFinite()) throw InputError("control input", "time step " + std::to_string(k) + ": not finite");
    validate(Z, k);
    stats_.resize(set_.particles().size());
    const ParticleStepResult r =
        set_.step([&](std::size_t i, RandomStream& rng, const Particle& p, Particle& out) {
          auto map = std::make_shared<Map>();
          State x, x_estimate;
          const double log_increment = propagate(p, u, Z, rng, x, x_estimate, *map, stats_[i]);
          out.trajectory = std::make_shared<const Node>(x, x_estimate, k, p.trajectory);
          out.map = std::move(map);
          return log_increment;
        });
    FastSlamStepReport report;
    report.step = k;
    report.ess = r.ess;
    report.best_particle = static_cast<int>(r.best);
    report.resampled = r.resampled;
    report.landmarks = static_cast<int>(set_.best().map->landmarks.size());
    report.associated = stats_[r.best].associated;
    report.log_likelihood = stats_[r.best].log_likelihood;
    report.ms = watch.elapsed_ms();
    last_ = report;
  }

  const State& pose() const { return set_.pose(); }
  PoseList trajectory() const { return set_.trajectory(); }
  /// The highest-weight particle's proposal means, steps 0..k.
  PoseList estimated_trajectory() const { return set_.estimated_trajectory(); }
  /// The highest-weight particle's landmarks ("ml": those detected at least estimate_min_detections times);
  /// label index = landmark id, existence 1.
  LandmarkList landmarks() const {
    LandmarkList out;
    for (const auto& l : set_.best().map->landmarks) {
      if (!known_ && l.detections < config_.estimate_min_detections) continue;
      LandmarkEstimate<Meas> e;
      e.label = Label{0, static_cast<std::int32_t>(l.id)};
      e.mean = l.mean;
      e.cov = l.cov;
      e.existence = 1.0;
      out.push_back(e);
    }
    return out;
  }
  const Map& map() const { return *set_.best().map; }
  const FastSlamStepReport& last_report() const { return last_; }
  int steps() const { return set_.steps(); }
  int resample_count() const { return set_.resample_count(); }
  const std::vector<Particle>& particles() const { return set_.particles(); }
  const FastSlamConfig& config() const { return config_; }

 private:
  struct ParticleStats {
    int associated = 0;
    double log_likelihood = 0.0;
  };
  struct Workspace {
    std::vector<std::pair<int, int>> pairs;  ///< (z index, landmark index in the prior map)
    std::vector<int> fresh;                  ///< z indices that start a landmark
    std::vector<std::tuple<double, int, int>> candidates;
    std::vector<int> near;
    std::vector<char> z_used, lm_used;
  };
  static Workspace& workspace() {
    static thread_local Workspace ws;
    return ws;
  }

  static const FastSlamConfig& validated(const FastSlamConfig& config) {
    validate_fastslam_config(config);
    return config;
  }

  void validate(const MeasurementSet& Z, int step) const {
    for (std::size_t j = 0; j < Z.size(); ++j) {
      if (!model_.is_finite(Z[j]))
        throw InputError("measurement set", "time step " + std::to_string(step) + ": measurement " +
                                                std::to_string(j) + " is not finite");
    }
    if (known_ && labels_.size() != Z.size())
      throw std::invalid_argument(
          "FastSlam2: 'known' association needs one label per measurement (time step " +
          std::to_string(step) + ")");
  }

  /// The id of the landmark measurement j starts ("known": its label, −1 for clutter; "ml": the next id).
  std::int64_t new_landmark_id(int j, const Map& map) const {
    return known_ ? static_cast<std::int64_t>(labels_[static_cast<std::size_t>(j)]) : map.next_id;
  }

  void add_landmark(const State& x, const Measurement& z, std::int64_t id, Map& map) const {
    LandmarkType l;
    l.id = id;
    model_.initialize(x, z, &l.mean, &l.cov);
    l.detections = 1;
    l.score = 1.0;
    map.insert(l);
  }

  /// Steps 2–5 for one particle; returns the log weight increment.
  double propagate(const Particle& p, const Control& u, const MeasurementSet& Z, RandomStream& rng, State& x,
                   State& x_estimate, Map& map, ParticleStats& st) const {
    Workspace& ws = workspace();
    const Map& prior = *p.map;
    const State x_pred = motion_.predict(p.trajectory->pose, u);
    const Covariance P_pred = motion_.process_noise(p.trajectory->pose, u);
    associate(prior, x_pred, P_pred, Z, ws);
    // 3. sequential FastSLAM 2.0 proposal
    State x_bar = x_pred;
    Covariance P_bar = P_pred;
    double log_increment = 0.0;
    typename Meas::PoseJacobian Hx;
    typename Meas::LandmarkJacobian Hm;
    for (const auto& [j, n] : ws.pairs) {
      const LandmarkType& l = prior.landmarks[static_cast<std::size_t>(n)];
      const Measurement zhat = model_.linearize(x_bar, l.mean, &Hx, &Hm);
      const Measurement nu = model_.residual(Z[static_cast<std::size_t>(j)], zhat);
      const typename Meas::MeasurementCovariance S_m = Hm * l.cov * Hm.transpose() + model_.noise();
      const typename Meas::MeasurementCovariance S = Hx * P_bar * Hx.transpose() + S_m;
      const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
      if (llt.info() != Eigen::Success) continue;
      log_increment += log_gaussian(nu, S);
      const Eigen::Matrix<double, Motion::kDim, Meas::kMeasDim> K = llt_solve(llt, Hx * P_bar).transpose();
      x_bar = Motion::retract(x_bar, K * nu);
      const Covariance I_KH = Covariance::Identity() - K * Hx;
      P_bar = I_KH * P_bar * I_KH.transpose() + K * S_m * K.transpose();
      symmetrize(P_bar);
    }
    x_estimate = x_bar;
    x = use_mean_ ? x_bar : Motion::retract(x_bar, rng.gaussian<Motion::kDim>(Tangent::Zero(), P_bar));
    if (!known_) log_increment += log_p0_ * static_cast<double>(ws.fresh.size());
    // 5. the map at x
    map.landmarks = prior.landmarks;
    map.next_id = prior.next_id;
    ws.lm_used.assign(prior.landmarks.size(), 0);
    for (const auto& [j, n] : ws.pairs) {
      LandmarkType& l = map.landmarks[static_cast<std::size_t>(n)];
      ws.lm_used[static_cast<std::size_t>(n)] = 1;
      const Measurement zhat = model_.linearize(x, l.mean, nullptr, &Hm);
      const typename Meas::MeasurementCovariance S = Hm * l.cov * Hm.transpose() + model_.noise();
      const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
      if (llt.info() != Eigen::Success) continue;
      const Eigen::Matrix<double, Meas::kLandmarkDim, Meas::kMeasDim> K =
          llt_solve(llt, Hm * l.cov).transpose();
      l.mean += K * model_.residual(Z[static_cast<std::size_t>(j)], zhat);
      const typename Meas::LandmarkCovariance I_KH = Meas::LandmarkCovariance::Identity() - K * Hm;
      l.cov = I_KH * l.cov * I_KH.transpose() + K * model_.noise() * K.transpose();
      symmetrize(l.cov);
      ++l.detections;
      l.score += 1.0;
    }
    if (!known_ && config_.remove_unconfirmed) {
      std::size_t kept = 0;
      for (std::size_t n = 0; n < map.landmarks.size(); ++n) {
        LandmarkType& l = map.landmarks[n];
        if (!ws.lm_used[n]) l.score -= model_.detection_probability(x, l.mean);
        if (l.score >= 0.0) map.landmarks[kept++] = l;
      }
      map.landmarks.resize(kept);
    }
    for (const int j : ws.fresh) {
      const std::int64_t id = new_landmark_id(j, map);
      add_landmark(x, Z[static_cast<std::size_t>(j)], id, map);
    }
    st.associated = static_cast<int>(ws.pairs.size());
    st.log_likelihood = log_increment;
    return log_increment;
  }

  /// Step 2: ws.pairs (sorted by z index) and ws.fresh.
  void associate(const Map& prior, const State& x_pred, const Covariance& P_pred, const MeasurementSet& Z,
                 Workspace& ws) const {
    ws.pairs.clear();
    ws.fresh.clear();
    const int M = static_cast<int>(Z.size());
    if (known_) {
      for (int j = 0; j < M; ++j) {
        const int label = labels_[static_cast<std::size_t>(j)];
        if (label < 0) continue;
        const int n = prior.find(label);
        if (n >= 0)
          ws.pairs.emplace_back(j, n);
        else
          ws.fresh.push_back(j);
      }
      return;
    }
    // landmarks near the predicted pose (the sensor range plus 3σ of the position uncertainty)
    constexpr int kPos = decltype(Meas::position(std::declval<State>()))::RowsAtCompileTime;
    const double margin = 3.0 * std::sqrt(std::max(0.0, P_pred.template topLeftCorner<kPos, kPos>().trace()));
    const double radius = model_.query_radius() + margin;
    const auto p = Meas::position(x_pred);
    ws.candidates.clear();
    typename Meas::PoseJacobian Hx;
    typename Meas::LandmarkJacobian Hm;
    for (std::size_t n = 0; n < prior.landmarks.size(); ++n) {
      const LandmarkType& l = prior.landmarks[n];
      if ((Meas::landmark_position(l.mean) - p).squaredNorm() > radius * radius) continue;
      const Measurement zhat = model_.linearize(x_pred, l.mean, &Hx, &Hm);
      const typename Meas::MeasurementCovariance S =
          Hm * l.cov * Hm.transpose() + Hx * P_pred * Hx.transpose() + model_.noise();
      const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
      if (llt.info() != Eigen::Success) continue;
      double log_det = 0.0;
      for (int i = 0; i < Meas::kMeasDim; ++i) log_det += std::log(llt.matrixLLT()(i, i));
      const double log_norm = -0.5 * Meas::kMeasDim * std::log(2.0 * M_PI) - log_det;
      for (int j = 0; j < M; ++j) {
        const double d2 =
            llt.matrixL().solve(model_.residual(Z[static_cast<std::size_t>(j)], zhat)).squaredNorm();
        if (!(d2 <= config_.gate_threshold)) continue;
        const double log_lik = log_norm - 0.5 * d2;
        if (log_lik >= log_p0_) ws.candidates.emplace_back(log_lik, j, static_cast<int>(n));
      }
    }
    std::sort(ws.candidates.begin(), ws.candidates.end(), [](const auto& a, const auto& b) {
      return std::get<0>(a) != std::get<0>(b)
                 ? std::get<0>(a) > std::get<0>(b)
                 : std::tie(std::get<1>(a), std::get<2>(a)) < std::tie(std::get<1>(b), std::get<2>(b));
    });
    ws.z_used.assign(static_cast<std::size_t>(M), 0);
    ws.lm_used.assign(prior.landmarks.size(), 0);
    for (const auto& [log_lik, j, n] : ws.candidates) {
      if (ws.z_used[static_cast<std::size_t>(j)] || ws.lm_used[static_cast<std::size_t>(n)]) continue;
      ws.z_used[static_cast<std::size_t>(j)] = 1;
      ws.lm_used[static_cast<std::size_t>(n)] = 1;
      ws.pairs.emplace_back(j, n);
    }
    std::sort(ws.pairs.begin(), ws.pairs.end());
    for (int j = 0; j < M; ++j)
      if (!ws.z_used[static_cast<std::size_t>(j)]) ws.fresh.push_back(j);
  }

  Motion motion_;
  Meas model_;
  FastSlamConfig config_;
  bool known_ = false;
  bool use_mean_ = false;
  double log_p0_ = 0.0;
  ParticleSet<State, Map> set_;
  std::vector<int> labels_;
  std::vector<ParticleStats> stats_;
  FastSlamStepReport last_;
};

}  // namespace glmbslam::backend
