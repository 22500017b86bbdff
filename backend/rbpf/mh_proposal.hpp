#pragma once
// The multi-hypothesis importance density (MH-ID) of paper 003 (PHD-SLAM 3.0; digest 2.4–2.5) for a
// particle's landmark map. Same interface as OptimalProposal (build / sample / log_density): GlmbSlam
// (δ-GLMB map) and PhdSlam (GM-PHD map, = PHD-SLAM 3.0) select it with proposal "mh".
//
// build(map, x̄, P̄, Z) = a map adapter (step 1) + one map-independent core (steps 2–5, build_from_landmarks):
//  1. Landmarks (adapter gather_mh_landmarks(map, model, x̄, margin, out), overloaded per map type and found
//  by
//     argument-dependent lookup): the landmarks in view at x̄ (with a fov_margin_sigmas × position-σ margin),
//     each with one Gaussian and a weight η (capped at 1 by the core):
//       δ-GLMB (here): label ℓ, η_ℓ = Σ_h ω_h [ℓ ∈ I_h] (its existence probability across the hypotheses) and
//                      the ω-weighted moment match of its tracks (one track per label in most maps);
//       GM-PHD (backend/phd/phd_mh_landmarks.hpp): every component, η = its GM weight (digest 2.4).
//  2. Log-likelihood table (Eq. 29–31, pose-marginal innovation of the REF-CODE):
//       log ℓ^{i,j} = log(η_i p_D^i) − log κ(z_j) + log N(z_j; h(m̂_i, x̄), H_m P_i H_mᵀ + H_x P̄ H_xᵀ + R)
//       (−∞ outside the χ² gate), log ℓ^{i,0} = log(1 − η_i p_D^i)   (Bernoulli form: a label that may not
//       exist is "missed" with probability 1 − η p_D; for η = 1 this is Eq. 31 exactly).
//     p_D is evaluated at the landmark mean and x̄. Landmarks that gate with no measurement and measurements
//     that gate with no landmark take no part in the ranking (they are missed / clutter in every hypothesis).
//  3. Murty's ranked assignments (backend/rbpf/murty.hpp): at most Γ̄ = max_assignments, stopping when an
//     assignment is less than assignment_ratio (1e-3) as likely as the best; plus the all-clutter assignment
//     (all landmarks missed) when the ranking did not already contain it — so it is always a component.
//  4. Per assignment t: moments (μ^t, Σ^t) by iterated posterior linearisation with the partitioned update
//     (digest 2.5 Algorithm 1, first-order SLR; L = ipl_iterations, stop when KL < ipl_tolerance); the all-
//     clutter component keeps the prior (x̄, P̄).
//  5. Component weights (Eq. 44, Bernoulli form as in 2.; weights "eq44", the default):
//       log κ^t = Σ_{i missed} log(1 − η_i p_D^i) + Σ_{i→j} [log(η_i p_D^i) − log κ(z_j)
//                 + log N(z_j; h(m̂_i, μ^t), G_x Σ^t G_xᵀ + G_m P_i G_mᵀ + R)]   (G_x, ẑ at μ^t)
//     normalised with log-sum-exp (they sum to one). Option weights "prior_predictive": log κ^t = log γ^t,
//     the ranked assignment's weight from 2. at x̄ (plus the miss terms of the landmarks left out of the
//     ranking).
// sample: t ~ Categorical(κ̃), then x ~ N(μ^t, Σ^t) (retracted on the pose manifold); log_density is the full
// mixture log Σ_t κ̃^t N(x; μ^t, Σ^t), so the importance weight w·Ĝ(x)·f(x|x⁻,u)/q(x) uses the mixture (Eq.
// 45). build() draws no random numbers: its result depends only on (map, x̄, P̄, Z), so particles that share a
// parent (resampled copies) can reuse one result exactly (GlmbSlam and PhdSlam build once per parent).
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "backend/glmb/glmb_map.hpp"
#include "backend/rbpf/mh_proposal_config.hpp"
#include "backend/rbpf/murty.hpp"
#include "backend/rbpf/pose_mixture.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

/// One landmark of the MH-ID (step 1 above): Gaussian position and weight η (capped at 1 by the core).
template <class Meas>
struct MhLandmark {
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  double weight = 1.0;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
template <class Meas>
using MhLandmarkList = std::vector<MhLandmark<Meas>, Eigen::aligned_allocator<MhLandmark<Meas>>>;

/// Iterated posterior linearisation with the partitioned (one measurement at a time) update, paper 003
/// Algorithm 1 with first-order statistical linear regression. Pairs (landmark mean, landmark covariance,
/// measurement) are applied in order to the prior (x̄, P̄), relinearising at the previous iterate. Returns the
/// number of iterations run. If an iterate's covariance is not positive definite the previous one is kept.
template <class Motion, class Meas, class PairRange>
int ipl_partitioned_update(const Meas& model, const typename Motion::State& x_pred,
                           const typename Motion::Covariance& P_pred, const PairRange& pairs, int iterations,
                           double tolerance, typename Motion::State& mean_out,
                           typename Motion::Covariance& cov_out) {
  using State = typename Motion::State;
  using Covariance = typename Motion::Covariance;
  using Tangent = typename Motion::Tangent;
  constexpr int kDim = Motion::kDim;
  State lin = x_pred;
  Covariance lin_cov = P_pred;
  int run = 0;
  for (int l = 0; l < iterations; ++l) {
    State mu = x_pred;
    Covariance Sig = P_pred;
    bool ok = true;
    for (const auto& pr : pairs) {
      typename Meas::PoseJacobian A;
      typename Meas::LandmarkJacobian Hm;
      const typename Meas::Measurement zhat = model.linearize(lin, pr.mean, &A, &Hm);
      const typename Meas::MeasurementCovariance Omega = Hm * pr.cov * Hm.transpose() + model.noise();
      // ν = z − (ẑ + A (μ ⊖ μ̃))   (Eq. 43b)
      const typename Meas::Measurement nu = model.residual(pr.z, zhat) - A * Motion::local(mu, lin);
      const typename Meas::MeasurementCovariance S = A * Sig * A.transpose() + Omega;  // Eq. 43c
      const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
      if (llt.info() != Eigen::Success) {
        ok = false;
        break;
      }
      const Eigen::Matrix<double, kDim, Meas::kMeasDim> K = llt.solve(A * Sig).transpose();  // Σ Aᵀ S⁻¹
      mu = Motion::retract(mu, K * nu);
      Sig -= K * S * K.transpose();
      symmetrize(Sig);
    }
    if (!ok || Eigen::LLT<Covariance>(Sig).info() != Eigen::Success) break;  // keep the previous iterate
    ++run;
    bool converged = false;
    if (l > 0) {  // KL( N(μ̃_{l−1}, Σ̃_{l−1}) ‖ N(μ, Σ) )
      const Eigen::LLT<Covariance> l1(Sig), l0(lin_cov);
      const Tangent d = Motion::local(mu, lin);
      double log_det1 = 0.0, log_det0 = 0.0;
      for (int i = 0; i < kDim; ++i) {
        log_det1 += 2.0 * std::log(l1.matrixLLT()(i, i));
        log_det0 += 2.0 * std::log(l0.matrixLLT()(i, i));
      }
      const double kl = 0.5 * (l1.solve(lin_cov).trace() - kDim + d.dot(l1.solve(d)) + log_det1 - log_det0);
      converged = kl < tolerance;
    }
    lin = mu;
    lin_cov = Sig;
    if (converged) break;
  }
  mean_out = lin;
  cov_out = lin_cov;
  return run;
}

/// Step 1 for a δ-GLMB map: the labels with a track in view at x̄ (find_active with the given margin), each
/// with η_ℓ = Σ_h ω_h [ℓ ∈ I_h] and the ω-weighted moment match of its tracks.
template <class Meas>
void gather_mh_landmarks(const GlmbMap<Meas>& map, const Meas& model, const typename Meas::Pose& x_pred,
                         double margin, MhLandmarkList<Meas>& out) {
  struct Scratch {
    std::vector<char> active;
    std::vector<double> track_weight, slot_weight;
    std::vector<int> slot_of_track;
    std::unordered_map<std::uint64_t, int> label_slot;
  };
  thread_local Scratch ws;
  out.clear();
  map.find_active(model, x_pred, margin, ws.active);
  ws.track_weight.assign(map.tracks.size(), 0.0);
  bool any = false;
  for (std::size_t t = 0; t < map.tracks.size(); ++t) any = any || ws.active[t];
  if (!any) return;
  for (const auto& h : map.hypotheses) {
    const double w = std::exp(h.log_weight);
    for (std::uint32_t t : h.tracks)
      if (ws.active[t]) ws.track_weight[t] += w;
  }
  ws.label_slot.clear();
  ws.slot_weight.clear();
  ws.slot_of_track.assign(map.tracks.size(), -1);
  for (std::size_t t = 0; t < map.tracks.size(); ++t) {  // weights and weighted means per label
    if (!ws.active[t] || ws.track_weight[t] <= 0.0) continue;
    const auto [it, inserted] =
        ws.label_slot.emplace(map.tracks[t].label.key(), static_cast<int>(out.size()));
    if (inserted) {
      MhLandmark<Meas> lm;
      lm.mean.setZero();
      lm.cov.setZero();
      out.push_back(lm);
      ws.slot_weight.push_back(0.0);
    }
    const int s = it->second;
    ws.slot_of_track[t] = s;
    ws.slot_weight[s] += ws.track_weight[t];
    out[s].mean += ws.track_weight[t] * map.tracks[t].mean;
  }
  for (std::size_t s = 0; s < out.size(); ++s) out[s].mean /= ws.slot_weight[s];
  for (std::size_t t = 0; t < map.tracks.size(); ++t) {
    const int s = ws.slot_of_track[t];
    if (s < 0) continue;
    const auto d = (map.tracks[t].mean - out[s].mean).eval();
    out[s].cov += ws.track_weight[t] * (map.tracks[t].cov + d * d.transpose());
  }
  for (std::size_t s = 0; s < out.size(); ++s) {
    out[s].cov /= ws.slot_weight[s];
    out[s].weight = ws.slot_weight[s];
  }
}

template <class Motion, class Meas>
class MhProposal {
 public:
  static constexpr int kDim = Motion::kDim;
  using State = typename Motion::State;
  using Tangent = typename Motion::Tangent;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;

  struct Component {
    double log_weight = 0.0;  ///< normalised: Σ exp = 1
    State mean;
    Covariance cov;
    int detections = 0;  ///< landmarks detected in this assignment (0 = the all-clutter component)
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  struct Result {
    std::vector<Component, Eigen::aligned_allocator<Component>> components;
    double log_marginal = kLogZero;  ///< log Σ_t κ^t (unnormalised Eq. 44 weights, all-clutter included)
    int landmarks_in_view = 0;
    int ranked = 0;  ///< assignments returned by Murty
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };

  MhProposal(const Motion& motion, const Meas& model, const MhProposalConfig& config)
      : motion_(motion), model_(model), config_(config) {}
  const MhProposalConfig& config() const { return config_; }

  /// Steps 1–5 for any map with a gather_mh_landmarks overload (δ-GLMB here, GM-PHD in backend/phd).
  template <class Map>
  void build(const Map& map, const State& x_pred, const Covariance& P_pred, const MeasurementSet& Z,
             RandomStream& /*rng: unused, build is deterministic*/, Result& out) const {
    Workspace& ws = workspace();
    const double pos_sigma = std::sqrt(std::max(0.0, P_pred.template topLeftCorner<2, 2>().trace()));
    gather_mh_landmarks(map, model_, x_pred, config_.fov_margin_sigmas * pos_sigma, ws.gathered);
    build_from_landmarks(ws.gathered, x_pred, P_pred, Z, out);
  }

  /// Steps 2–5 (the map-independent core) for the given in-view landmarks.
  void build_from_landmarks(const MhLandmarkList<Meas>& landmarks, const State& x_pred,
                            const Covariance& P_pred, const MeasurementSet& Z, Result& out) const {
    Workspace& ws = workspace();
    out.components.clear();
    out.ranked = 0;
    set_landmarks(landmarks, x_pred, ws);
    const int M = static_cast<int>(ws.lm.size());
    const int J = static_cast<int>(Z.size());
    out.landmarks_in_view = M;
    // all-clutter weight Σ_i log(1 − η_i p_D^i) and the log-likelihood table at x̄
    double log_all_miss = 0.0;
    ws.log_detect.resize(M, J);
    ws.log_miss.resize(M);
    for (int i = 0; i < M; ++i) {
      Landmark& lm = ws.lm[i];
      ws.log_miss(i) = lm.log_miss;
      log_all_miss += lm.log_miss;
      typename Meas::PoseJacobian Hx;
      typename Meas::LandmarkJacobian Hm;
      const Measurement zhat = model_.linearize(x_pred, lm.mean, &Hx, &Hm);
      const typename Meas::MeasurementCovariance S =
          Hm * lm.cov * Hm.transpose() + Hx * P_pred * Hx.transpose() + model_.noise();
      const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
      for (int j = 0; j < J; ++j) ws.log_detect(i, j) = kLogZero;
      if (lm.log_detect == kLogZero || llt.info() != Eigen::Success) continue;
      double log_det = 0.0;
      for (int d = 0; d < Meas::kMeasDim; ++d) log_det += std::log(llt.matrixLLT()(d, d));
      const double log_norm = -0.5 * Meas::kMeasDim * std::log(2.0 * M_PI) - log_det;
      for (int j = 0; j < J; ++j) {
        const double d2 = llt.matrixL().solve(model_.residual(Z[j], zhat)).squaredNorm();
        if (!(d2 <= config_.gate_threshold)) continue;
        ws.log_detect(i, j) = lm.log_detect - model_.log_clutter_intensity(Z[j]) + log_norm - 0.5 * d2;
      }
    }
    // reduce to the landmarks and measurements that gate with something
    ws.rows.clear();
    ws.cols.clear();
    for (int i = 0; i < M; ++i)
      if ((ws.log_detect.row(i).array() > kLogZero).any()) ws.rows.push_back(i);
    for (int j = 0; j < J; ++j)
      if (M > 0 && (ws.log_detect.col(j).array() > kLogZero).any()) ws.cols.push_back(j);
    bool have_all_clutter = false;
    ws.comp_log_w.clear();
    if (!ws.rows.empty() && !ws.cols.empty()) {
      Eigen::MatrixXd detect(ws.rows.size(), ws.cols.size());
      Eigen::VectorXd miss(ws.rows.size());
      for (std::size_t r = 0; r < ws.rows.size(); ++r) {
        miss(r) = ws.log_miss(ws.rows[r]);
        for (std::size_t c = 0; c < ws.cols.size(); ++c) detect(r, c) = ws.log_detect(ws.rows[r], ws.cols[c]);
      }
      MurtyOptions mo;
      mo.max_solutions = static_cast<std::size_t>(std::max(0, config_.max_assignments));
      mo.max_cost_gap = -std::log(config_.assignment_ratio);
      const std::vector<AssociationHypothesis> ranked = rank_associations(detect, miss, mo);
      out.ranked = static_cast<int>(ranked.size());
      for (const AssociationHypothesis& h : ranked) {
        ws.pairs.clear();
        for (std::size_t r = 0; r < ws.rows.size(); ++r) {
          const int c = h.measurement_of[r];
          if (c < 0) continue;
          const Landmark& lm = ws.lm[ws.rows[r]];
          ws.pairs.push_back(Pair{lm.mean, lm.cov, Z[ws.cols[c]], ws.rows[r]});
        }
        Component comp;
        comp.detections = static_cast<int>(ws.pairs.size());
        if (ws.pairs.empty()) {
          have_all_clutter = true;
          comp.mean = x_pred;
          comp.cov = P_pred;
          comp.log_weight = log_all_miss;
        } else {
          ipl_partitioned_update<Motion, Meas>(model_, x_pred, P_pred, ws.pairs, config_.ipl_iterations,
                                               config_.ipl_tolerance, comp.mean, comp.cov);
          if (config_.weights == "prior_predictive") {
            ws.detected.assign(ws.lm.size(), 0);
            for (std::size_t r = 0; r < ws.rows.size(); ++r) ws.detected[ws.rows[r]] = 1;
            comp.log_weight = h.log_weight;  // Σ log ℓ over the ranked rows (at x̄, pose-marginal S)
            for (int i = 0; i < M; ++i)
              if (!ws.detected[i]) comp.log_weight += ws.lm[i].log_miss;
          } else {
            comp.log_weight = component_log_weight(comp.mean, comp.cov, ws);
          }
        }
        if (comp.log_weight == kLogZero || !std::isfinite(comp.log_weight)) continue;
        out.components.push_back(comp);
      }
    }
    if (!have_all_clutter) {  // the all-clutter component: the motion prior
      Component comp;
      comp.mean = x_pred;
      comp.cov = P_pred;
      comp.log_weight = log_all_miss;
      comp.detections = 0;
      out.components.push_back(comp);
    }
    // normalise (Eq. 44)
    ws.comp_log_w.clear();
    for (const auto& c : out.components) ws.comp_log_w.push_back(c.log_weight);
    out.log_marginal = log_sum_exp(ws.comp_log_w);
    if (out.log_marginal == kLogZero || !std::isfinite(out.log_marginal)) {
      const double u = -std::log(static_cast<double>(out.components.size()));
      for (auto& c : out.components) c.log_weight = u;
    } else {
      for (auto& c : out.components) c.log_weight -= out.log_marginal;
    }
  }

  /// t ~ Categorical(κ̃), x ~ N(μ^t, Σ^t).
  State sample(const Result& q, RandomStream& rng) const {
    return draw_from_pose_mixture<Motion>(q.components, rng);
  }

  /// log q(x) = log Σ_t κ̃^t N(x ⊖ μ^t; 0, Σ^t).
  double log_density(const Result& q, const State& x) const {
    return log_pose_mixture_density<Motion>(q.components, x);
  }

  /// The mixture mean Σ_t κ̃^t μ^t, taken in the tangent space at the highest-weight component's mean.
  State mean(const Result& q) const {
    std::size_t best = 0;
    for (std::size_t c = 1; c < q.components.size(); ++c)
      if (q.components[c].log_weight > q.components[best].log_weight) best = c;
    const State& ref = q.components[best].mean;
    Tangent d = Tangent::Zero();
    for (const auto& c : q.components) d += std::exp(c.log_weight) * Motion::local(c.mean, ref);
    return Motion::retract(ref, d);
  }

 private:
  struct Landmark {
    typename Meas::Landmark mean;
    typename Meas::LandmarkCovariance cov;
    double log_detect = kLogZero;  ///< log(η p_D)
    double log_miss = 0.0;         ///< log(1 − η p_D)
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  struct Pair {
    typename Meas::Landmark mean;
    typename Meas::LandmarkCovariance cov;
    Measurement z;
    int landmark = 0;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  struct Workspace {
    MhLandmarkList<Meas> gathered;
    std::vector<Landmark, Eigen::aligned_allocator<Landmark>> lm;
    std::vector<int> rows, cols;
    Eigen::MatrixXd log_detect;
    Eigen::VectorXd log_miss;
    std::vector<Pair, Eigen::aligned_allocator<Pair>> pairs;
    std::vector<double> comp_log_w;
    std::vector<char> detected;
  };
  static Workspace& workspace() {
    static thread_local Workspace ws;
    return ws;
  }

  /// Per landmark: η = min(1, weight), p_D at x̄, log(η p_D) and log(1 − η p_D).
  void set_landmarks(const MhLandmarkList<Meas>& in, const State& x_pred, Workspace& ws) const {
    ws.lm.resize(in.size());
    for (std::size_t s = 0; s < in.size(); ++s) {
      Landmark& lm = ws.lm[s];
      lm.mean = in[s].mean;
      lm.cov = in[s].cov;
      const double eta = std::min(1.0, in[s].weight);
      const double pd = model_.detection_probability(x_pred, lm.mean);
      const double eta_pd = eta * pd;
      lm.log_detect = eta_pd > 0.0 ? std::log(eta_pd) : kLogZero;
      lm.log_miss = eta_pd < 1.0 ? std::log1p(-eta_pd) : kLogZero;
    }
  }

  /// Eq. 44 at the component's posterior moments: missed landmarks contribute log(1 − η p_D), detected ones
  /// log(η p_D) − log κ(z) + log N(z; h(m̂, μ^t), G_x Σ^t G_xᵀ + G_m P G_mᵀ + R).
  double component_log_weight(const State& mu, const Covariance& Sigma, Workspace& ws) const {
    ws.detected.assign(ws.lm.size(), 0);
    double lw = 0.0;
    for (const Pair& pr : ws.pairs) {
      ws.detected[pr.landmark] = 1;
      const Landmark& lm = ws.lm[pr.landmark];
      typename Meas::PoseJacobian Gx;
      typename Meas::LandmarkJacobian Gm;
      const Measurement zhat = model_.linearize(mu, pr.mean, &Gx, &Gm);
      const typename Meas::MeasurementCovariance S =
          Gx * Sigma * Gx.transpose() + Gm * pr.cov * Gm.transpose() + model_.noise();
      lw += lm.log_detect - model_.log_clutter_intensity(pr.z) + log_gaussian(model_.residual(pr.z, zhat), S);
    }
    for (std::size_t i = 0; i < ws.lm.size(); ++i)
      if (!ws.detected[i]) lw += ws.lm[i].log_miss;
    return lw;
  }

  Motion motion_;
  Meas model_;
  MhProposalConfig config_;
};

}  // namespace glmbslam::backend
