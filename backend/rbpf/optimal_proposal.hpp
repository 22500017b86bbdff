#pragma once
// The optimal-kernel proposal of δ-GLMB-SLAM 2.0 (paper 000 Eq. 30–32), as the step-by-step algorithm of
// digest 0.5:
//  1. x̄ = f(x⁻, u), P̄ = F_ε Q F_εᵀ + regulariser (P_x = 0 for a sampled particle).
//  2. The highest-weight map hypotheses (proposal_hypotheses, weight ≥ proposal_min_weight; the best always).
//  3. Per hypothesis: association hypotheses θ from the Gibbs sampler at x̄ with the pose-marginal innovation
//     S' = H_m P H_mᵀ + H_x P̄ H_xᵀ + R; weight W = ω_h Π_i η_i(θ_i). With rbpf.proposal_births (always, or
//     empty_view: when no mapped landmark is in view) the map's birth candidates (the adaptive-birth
//     Bernoullis the coming update creates from the previous scan, GlmbMap::births) are extra rows with the
//     η of a birth in the update (digest 0.2): not born 1 − r_B, born and missed r_B (1 − p_D), born and
//     detected r_B p_D N(z_j; ẑ, S')/κ(z_j); a birth that gates with no measurement only multiplies every W
//     by 1 − r_B p_D (marginalised as in the update). At step 1 after GlmbSlam::initial_scan the map is
//     empty and these rows are what ties x_1 to the known x_0 (without them x_1 is a draw from the prior).
//  4. Per (h, θ): the FastSLAM-2.0 Gaussian by partitioned KF updates of (x̄, P̄) with every detection of θ,
//     relinearised up to ipl_iterations times (paper 003 Algorithm 1, first-order), stopping when the KL
//     divergence between successive iterates is below ipl_tolerance.
//  5. Components normalised; moment-matched to one Gaussian (what paper 000 does), or kept as a mixture.
// log Σ W (over every association hypothesis found in round 0) is Eq. 33's marginal, used by the "paper"
// weighting. η includes the update's descriptor likelihood ratio when the model has one (appearance.hpp), so
// that the proposal weighs an association as the update will.
//
// The draw (rbpf.proposal_scale s): after step 5 every covariance of the result is multiplied by s, so that
// sample() and log_density() are those of the narrower density the particle draws from; s = 0 keeps the
// covariances and sample() returns the mean (of a component drawn by weight for a mixture), whose weight
// f/q · Ĝ is then the Laplace approximation of the marginal likelihood.
//
// Association rounds (rbpf.proposal_association_rounds). Step 3 scores every landmark with the pose-marginal
// S', as if each landmark saw its own independent draw of the pose error: Π_i ∫ η_i(θ_i | x) N(x; x̄, P̄) dx
// instead of ∫ Π_i η_i(θ_i | x) N(x; x̄, P̄) dx. With a tight P̄ the two agree; with a wide one (a fallback Q, a
// still camera with an inflated Q) every landmark gates with several measurements whose S'-likelihoods are
// alike, and the best hypothesis mixes right and wrong pairings (a still camera with a 0.5 m / 0.02 rad
// prior: about half of its pairs wrong), which the Gaussian of step 4 then fuses: the pose moves centimetres
// to decimetres, the update at that pose explains half the scan with births, and the map no longer pins the
// pose. So: if a detection of the best hypothesis fails the gate at the pose N(μ, Σ) that hypothesis implies,
// steps 3–5 are repeated at N(μ, Σ) (the exact collapsed conditional of one landmark's association given the
// others uses the pose conditioned on them, ≈ N(μ, Σ) when they are many), until the best association no
// longer changes or the rounds are used up; the Gaussians are always computed from the prior (x̄, P̄).
// A wide prior thus widens the first search, and the rounds restore the joint association the map implies.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "backend/glmb/gate_bound.hpp"
#include "backend/glmb/gibbs_sampler.hpp"
#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/llt_solve.hpp"
#include "backend/rbpf/pose_mixture.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "core/error.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

template <class Motion, class Meas>
class OptimalProposal {
 public:
  static constexpr int kDim = Motion::kDim;
  using State = typename Motion::State;
  using Tangent = typename Motion::Tangent;
  using Covariance = typename Motion::Covariance;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;

  struct Component {
    double log_weight = 0.0;  ///< normalised over the kept components
    State mean;
    Covariance cov;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  struct Result {
    std::vector<Component, Eigen::aligned_allocator<Component>> components;
    State mean;                      ///< moment match
    Covariance cov;                  ///< moment match
    double log_marginal = kLogZero;  ///< log Σ_{h,θ} W_{h,θ}
    bool mixture = false;
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };

  OptimalProposal(const Motion& motion, const Meas& model, const RbpfConfig& config)
      : motion_(motion),
        model_(model),
        config_(config),
        use_mean_(config.particles == 1 && config.single_particle == "mean"),
        scale_(config.proposal_scale),
        births_(parse_births(config.proposal_births)) {}

  void build(const GlmbMap<Meas>& map, const State& x_pred, const Covariance& P_pred, const MeasurementSet& Z,
             RandomStream& rng, Result& out) const {
    Workspace& ws = workspace();
    const double gate =
        config_.proposal_gate_threshold > 0.0 ? config_.proposal_gate_threshold : config_.glmb.gate_threshold;
    // active tracks, with a margin for the pose uncertainty
    // (the position part of the tangent comes first: (x, y) for 2D poses, ρ for SE(3))
    constexpr int kPos = decltype(Meas::position(std::declval<State>()))::RowsAtCompileTime;
    const double pos_sigma = std::sqrt(std::max(0.0, P_pred.template topLeftCorner<kPos, kPos>().trace()));
    map.find_active(model_, x_pred, config_.glmb.fov_margin + 3.0 * pos_sigma, ws.active, &ws.track_pd);
    // round 0: the association hypotheses at the prediction (x̄, P̄), step 3
    associate(map, x_pred, P_pred, Z, gate, rng, ws);
    out.log_marginal = log_sum_exp(ws.cand_log_w);
    out.mixture = config_.proposal_mixture;
    make_components(map, Z, x_pred, P_pred, x_pred, ws, out.components);
    // further rounds while the best hypothesis is not consistent with the pose it implies (see the file
    // comment: the pose-marginal S' of round 0 treats the pose error as independent per landmark)
    for (int round = 1; round < config_.proposal_association_rounds && !out.components.empty(); ++round) {
      const Component best = out.components.front();
      if (round == 1 ? consistent(map, Z, gate, ws, best) : same_association(ws)) break;
      best_pairs(ws, ws.previous_best);
      associate(map, best.mean, best.cov, Z, gate, rng, ws);
      make_components(map, Z, x_pred, P_pred, best.mean, ws, ws.next_components);
      if (ws.next_components.empty()) break;  // keep the previous round's components
      std::swap(out.components, ws.next_components);
    }
    if (out.components.empty()) {  // no map in view: the motion prior
      Component comp;
      comp.mean = x_pred;
      comp.cov = P_pred;
      out.components.push_back(comp);
    }
    // moment match in the tangent space at x̄
    Tangent d_mean = Tangent::Zero();
    for (const auto& c : out.components) d_mean += std::exp(c.log_weight) * Motion::local(c.mean, x_pred);
    out.mean = Motion::retract(x_pred, d_mean);
    out.cov.setZero();
    for (const auto& c : out.components) {
      const Tangent d = Motion::local(c.mean, out.mean);
      out.cov += std::exp(c.log_weight) * (c.cov + d * d.transpose());
    }
    symmetrize(out.cov);
    if (scale_ > 0.0 && scale_ != 1.0) {  // the draw density (rbpf.proposal_scale)
      out.cov *= scale_;
      for (auto& c : out.components) c.cov *= scale_;
    }
  }

  /// Draws x ~ q (the moment-matched Gaussian, or the mixture); its mean with one particle and
  /// single_particle "mean"; with proposal_scale 0 the mean (a mixture: the mean of a component drawn by
  /// weight).
  State sample(const Result& q, RandomStream& rng) const {
    if (use_mean_) return q.mean;
    if (scale_ == 0.0)
      return q.mixture ? q.components[draw_mixture_component(q.components, rng)].mean : q.mean;
    if (!q.mixture) return Motion::retract(q.mean, rng.gaussian<kDim>(Tangent::Zero(), q.cov));
    return draw_from_pose_mixture<Motion>(q.components, rng);
  }

  /// log q(x).
  double log_density(const Result& q, const State& x) const {
    if (!q.mixture) return log_gaussian(Motion::local(x, q.mean), q.cov);
    return log_pose_mixture_density<Motion>(q.components, x);
  }

 private:
  struct Workspace {
    std::vector<char> active;
    std::vector<int> source_of_track, source_begin, entry_column, row_track, row_source, samples, cand_begin,
        order, birth_source;  ///< birth_source: the birth candidates with a row (index into GlmbMap::births)
    std::vector<double> entry_log_eta, cand_log_w, track_pd;
    std::vector<std::pair<int, int>>
        cand_pairs;            ///< (landmark id: track index, or n_tracks + birth; z index)
    AssociationTable sources;  ///< one row per active track
    GibbsWorkspace gibbs;
    int best_cand = -1;  ///< the candidate of the first component (make_components)
    std::vector<std::pair<int, int>> previous_best, current_best;  ///< the best candidate's pairs, sorted
    std::vector<Component, Eigen::aligned_allocator<Component>> next_components;
  };

  /// Step 3 at the pose Gaussian N(x_lin, P_lin) (the prediction in round 0, the best component of the
  /// previous round after): the sampler's rows (active tracks of ws.active, then with proposal_births the
  /// birth candidates that gate), and per chosen map hypothesis the distinct Gibbs solutions as candidates
  /// (ws.cand_log_w, ws.cand_begin, ws.cand_pairs).
  void associate(const GlmbMap<Meas>& map, const State& x_lin, const Covariance& P_lin,
                 const MeasurementSet& Z, double gate, RandomStream& rng, Workspace& ws) const {
    const int M = static_cast<int>(Z.size());
    const int n_tracks = static_cast<int>(map.tracks.size());
    ws.source_of_track.assign(n_tracks, -1);
    ws.source_begin.clear();
    ws.entry_column.clear();
    ws.entry_log_eta.clear();
    int num_active = 0;
    for (int t = 0; t < n_tracks; ++t) {
      if (!ws.active[t]) continue;
      const auto& tr = map.tracks[t];
      ws.source_of_track[t] = num_active++;
      const double ps = model_.survival_probability(x_lin, tr.mean);
      // p_D(tr.mean | x̄) from find_active
      add_row(ws, x_lin, P_lin, Z, gate, tr.mean, tr.cov, tr.appearance, std::log(ps),
              ps < 1.0 ? std::log1p(-ps) : kLogZero, ws.track_pd[t]);
    }
    ws.birth_source.clear();
    double log_birth_factor = 0.0;  // Π (1 − r_B p_D) over the births that gate with no measurement
    if (births_ == Births::kAlways || (births_ == Births::kEmptyView && num_active == 0)) {
      for (std::size_t b = 0; b < map.births.size(); ++b) {
        const auto& bc = map.births[b];
        const double log_r = bc.log_existence;
        const double log_1mr = log_r < 0.0 ? std::log(-std::expm1(log_r)) : kLogZero;
        const int first = static_cast<int>(ws.entry_column.size());
        if (add_row(ws, x_lin, P_lin, Z, gate, bc.mean, bc.cov, bc.appearance, log_r, log_1mr,
                    model_.detection_probability(x_lin, bc.mean))) {
          ws.birth_source.push_back(static_cast<int>(b));
          continue;
        }
        log_birth_factor += log_sum_exp(ws.entry_log_eta.begin() + first, ws.entry_log_eta.end());
        ws.entry_column.resize(first);
        ws.entry_log_eta.resize(first);
        ws.source_begin.pop_back();
      }
    }
    const int num_sources = num_active + static_cast<int>(ws.birth_source.size());
    ws.source_begin.push_back(static_cast<int>(ws.entry_column.size()));
    // the sampler's rows, prepared once and shared by the chosen map hypotheses
    ws.sources.reset(M);
    for (int s = 0; s < num_sources; ++s) {
      for (int e = ws.source_begin[s]; e < ws.source_begin[s + 1]; ++e)
        ws.sources.add(ws.entry_column[e], ws.entry_log_eta[e]);
      ws.sources.end_row();
    }
    // association hypotheses per chosen map hypothesis
    ws.cand_log_w.clear();
    ws.cand_begin.clear();
    ws.cand_pairs.clear();
    const int n_hyp = std::min<int>(config_.proposal_hypotheses, static_cast<int>(map.hypotheses.size()));
    for (int hi = 0; hi < n_hyp; ++hi) {
      const Hypothesis& h = map.hypotheses[hi];
      if (hi > 0 && std::exp(h.log_weight) < config_.proposal_min_weight) break;
      ws.row_track.clear();
      ws.row_source.clear();
      for (std::uint32_t t : h.tracks) {
        const int s = ws.source_of_track[t];
        if (s < 0) continue;
        ws.row_track.push_back(static_cast<int>(t));
        ws.row_source.push_back(s);
      }
      for (std::size_t b = 0; b < ws.birth_source.size(); ++b) {  // landmark id n_tracks + birth index
        ws.row_track.push_back(n_tracks + ws.birth_source[b]);
        ws.row_source.push_back(num_active + static_cast<int>(b));
      }
      const int rows = static_cast<int>(ws.row_source.size());
      ws.samples.clear();
      const int count =
          gibbs_sample(ws.sources, ws.row_source.data(), rows, rows == 0 ? 0 : config_.proposal_gibbs_samples,
                       rng, ws.gibbs, ws.samples, true);
      const int distinct = unique_solutions(ws.samples, rows, count);
      for (int c = 0; c < distinct; ++c) {
        const int* gamma = ws.samples.data() + static_cast<std::size_t>(c) * rows;
        const double lw = log_weight(ws, gamma, rows);
        if (lw == kLogZero) continue;
        ws.cand_log_w.push_back(h.log_weight + log_birth_factor + lw);
        ws.cand_begin.push_back(static_cast<int>(ws.cand_pairs.size()));
        for (int i = 0; i < rows; ++i)
          if (gamma[i] > 0) ws.cand_pairs.emplace_back(ws.row_track[i], gamma[i] - 1);
      }
    }
    ws.cand_begin.push_back(static_cast<int>(ws.cand_pairs.size()));
  }

  /// Steps 4–5 for the candidates of associate(): the proposal_max_components best, normalised, each the
  /// FastSLAM-2.0 Gaussian from the prior (x̄, P̄) first linearised at x_lin; the best first (ws.best_cand).
  void make_components(const GlmbMap<Meas>& map, const MeasurementSet& Z, const State& x_pred,
                       const Covariance& P_pred, const State& x_lin, Workspace& ws,
                       std::vector<Component, Eigen::aligned_allocator<Component>>& components) const {
    components.clear();
    const int n_cand = static_cast<int>(ws.cand_log_w.size());
    ws.order.resize(n_cand);
    for (int c = 0; c < n_cand; ++c) ws.order[c] = c;
    const int keep = std::min(n_cand, config_.proposal_max_components);
    std::partial_sort(ws.order.begin(), ws.order.begin() + keep, ws.order.end(), [&](int a, int b) {
      return ws.cand_log_w[a] != ws.cand_log_w[b] ? ws.cand_log_w[a] > ws.cand_log_w[b] : a < b;
    });
    ws.best_cand = keep > 0 ? ws.order[0] : -1;
    double log_total = kLogZero;
    for (int k = 0; k < keep; ++k) log_total = log_add(log_total, ws.cand_log_w[ws.order[k]]);
    for (int k = 0; k < keep; ++k) {
      const int c = ws.order[k];
      Component comp;
      comp.log_weight = ws.cand_log_w[c] - log_total;
      fastslam_gaussian(map, Z, x_pred, P_pred, x_lin, ws.cand_begin[c], ws.cand_begin[c + 1], ws, comp.mean,
                        comp.cov);
      components.push_back(comp);
    }
  }

  /// The detections of the best candidate, sorted.
  static void best_pairs(const Workspace& ws, std::vector<std::pair<int, int>>& out) {
    out.assign(ws.cand_pairs.begin() + ws.cand_begin[ws.best_cand],
               ws.cand_pairs.begin() + ws.cand_begin[ws.best_cand + 1]);
    std::sort(out.begin(), out.end());
  }
  /// Whether the best candidate makes the same detections as the previous round's.
  static bool same_association(Workspace& ws) {
    best_pairs(ws, ws.current_best);
    return ws.current_best == ws.previous_best;
  }
  /// Whether every detection of the best candidate (ws.best_cand) passes the gate at the pose Gaussian
  /// N(best.mean, best.cov) that the candidate implies, with S = H_x Σ H_xᵀ + H_m P H_mᵀ + R.
  bool consistent(const GlmbMap<Meas>& map, const MeasurementSet& Z, double gate, const Workspace& ws,
                  const Component& best) const {
    const int n_tracks = static_cast<int>(map.tracks.size());
    for (int k = ws.cand_begin[ws.best_cand]; k < ws.cand_begin[ws.best_cand + 1]; ++k) {
      const int id = ws.cand_pairs[k].first;
      const auto& mean = id < n_tracks ? map.tracks[id].mean : map.births[id - n_tracks].mean;
      const auto& cov = id < n_tracks ? map.tracks[id].cov : map.births[id - n_tracks].cov;
      typename Meas::PoseJacobian Hx;
      typename Meas::LandmarkJacobian Hm;
      const Measurement zhat = model_.linearize(best.mean, mean, &Hx, &Hm);
      const typename Meas::MeasurementCovariance S =
          Hm * cov * Hm.transpose() + Hx * best.cov * Hx.transpose() + model_.noise();
      const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
      if (llt.info() != Eigen::Success) return false;
      const double d2 = llt.matrixL().solve(model_.residual(Z[ws.cand_pairs[k].second], zhat)).squaredNorm();
      if (!(d2 <= gate)) return false;
    }
    return true;
  }
  /// log Π_i η_i(γ_i) over the rows ws.row_source (−∞ if some γ_i has no entry).
  static double log_weight(const Workspace& ws, const int* gamma, int rows) {
    double s = 0.0;
    for (int i = 0; i < rows; ++i) {
      const int r = ws.row_source[i];
      int e = ws.sources.row_begin(r);
      const int e_end = ws.sources.row_end(r);
      while (e < e_end && ws.sources.column(e) != gamma[i]) ++e;
      if (e == e_end) return kLogZero;
      s += ws.sources.log_eta(e);
    }
    return s;
  }
  static Workspace& workspace() {
    static thread_local Workspace ws;
    return ws;
  }
  static void push(Workspace& ws, int column, double log_eta) {
    ws.entry_column.push_back(column);
    ws.entry_log_eta.push_back(log_eta);
  }

  enum class Births { kNever, kEmptyView, kAlways };
  static Births parse_births(const std::string& s) {
    if (s == "never") return Births::kNever;
    if (s == "empty_view") return Births::kEmptyView;
    if (s == "always") return Births::kAlways;
    throw ConfigError("rbpf.proposal_births must be 'never', 'empty_view' or 'always'");
  }

  /// Opens a row of η for a landmark N(mean, cov) that exists with probability exp(log_exist) (p_S, or r_B
  /// for a birth): dead / not born, missed, and detected by each z_j inside the gate with the pose-marginal
  /// innovation S' = H_m P H_mᵀ + H_x P̄ H_xᵀ + R (digest 0.2 and 0.5 step 3). Returns true if some z_j gated.
  bool add_row(Workspace& ws, const State& x_pred, const Covariance& P_pred, const MeasurementSet& Z,
               double gate, const typename Meas::Landmark& mean, const typename Meas::LandmarkCovariance& cov,
               const typename AppearanceOf<Meas>::Type& appearance, double log_exist, double log_not_exist,
               double pd) const {
    ws.source_begin.push_back(static_cast<int>(ws.entry_column.size()));
    if (log_not_exist > kLogZero) push(ws, AssociationTable::kDead, log_not_exist);
    if (pd < 1.0) push(ws, AssociationTable::kMissed, log_exist + std::log1p(-pd));
    if (pd <= 0.0) return false;
    typename Meas::PoseJacobian Hx;
    typename Meas::LandmarkJacobian Hm;
    const Measurement zhat = model_.linearize(x_pred, mean, &Hx, &Hm);
    const typename Meas::MeasurementCovariance S =
        Hm * cov * Hm.transpose() + Hx * P_pred * Hx.transpose() + model_.noise();
    const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
    if (llt.info() != Eigen::Success) return false;
    double log_det = 0.0;
    for (int i = 0; i < Meas::kMeasDim; ++i) log_det += std::log(llt.matrixLLT()(i, i));
    const double log_norm = -0.5 * Meas::kMeasDim * std::log(2.0 * M_PI) - log_det;
    const double base = log_exist + std::log(pd);
    const Measurement diag_S = S.diagonal();
    bool gated = false;
    for (std::size_t j = 0; j < Z.size(); ++j) {
      const Measurement nu = model_.residual(Z[j], zhat);
      if (fails_gate_on_diagonal(nu, diag_S, gate)) continue;  // most pairs: no triangular solve
      const double d2 = llt.matrixL().solve(nu).squaredNorm();
      if (!(d2 <= gate)) continue;
      double log_eta = base + log_norm - 0.5 * d2 - model_.log_clutter_intensity(Z[j]);
      if constexpr (AppearanceOf<Meas>::kEnabled) {  // the update's descriptor likelihood ratio
        if (model_.uses_appearance()) log_eta += model_.log_appearance_ratio(appearance, static_cast<int>(j));
      }
      push(ws, static_cast<int>(j) + 1, log_eta);
      gated = true;
    }
    return gated;
  }

  static double kl_divergence(const State& m0, const Covariance& S0, const State& m1, const Covariance& S1) {
    const Eigen::LLT<Covariance> l1(S1);
    const Eigen::LLT<Covariance> l0(S0);
    if (l1.info() != Eigen::Success || l0.info() != Eigen::Success)
      return std::numeric_limits<double>::infinity();
    const Tangent d = Motion::local(m1, m0);
    double log_det1 = 0.0, log_det0 = 0.0;
    for (int i = 0; i < kDim; ++i) {
      log_det1 += 2.0 * std::log(l1.matrixLLT()(i, i));
      log_det0 += 2.0 * std::log(l0.matrixLLT()(i, i));
    }
    return 0.5 * ((l1.solve(S0)).trace() - kDim + d.dot(l1.solve(d)) + log_det1 - log_det0);
  }

  /// Partitioned, relinearised KF update of (x̄, P̄) with the detections [begin, end) of one hypothesis.
  void fastslam_gaussian(const GlmbMap<Meas>& map, const MeasurementSet& Z, const State& x_pred,
                         const Covariance& P_pred, const State& x_lin, int begin, int end, Workspace& ws,
                         State& mean_out, Covariance& cov_out) const {
    State lin = x_lin;
    Covariance lin_cov = P_pred;
    if (begin == end) {
      mean_out = x_pred;
      cov_out = P_pred;
      return;
    }
    for (int l = 0; l < config_.ipl_iterations; ++l) {
      State mu = x_pred;
      Covariance Sig = P_pred;
      for (int k = begin; k < end; ++k) {
        const int id = ws.cand_pairs[k].first;
        const int n_tracks = static_cast<int>(map.tracks.size());
        const auto& mean = id < n_tracks ? map.tracks[id].mean : map.births[id - n_tracks].mean;
        const auto& cov = id < n_tracks ? map.tracks[id].cov : map.births[id - n_tracks].cov;
        const Measurement& z = Z[ws.cand_pairs[k].second];
        typename Meas::PoseJacobian A;
        typename Meas::LandmarkJacobian Hm;
        const Measurement zhat = model_.linearize(lin, mean, &A, &Hm);
        const typename Meas::MeasurementCovariance Omega = Hm * cov * Hm.transpose() + model_.noise();
        const Measurement nu = model_.residual(z, zhat) - A * Motion::local(mu, lin);
        const typename Meas::MeasurementCovariance S = A * Sig * A.transpose() + Omega;
        const Eigen::LLT<typename Meas::MeasurementCovariance> llt(S);
        if (llt.info() != Eigen::Success) continue;
        const Eigen::Matrix<double, kDim, Meas::kMeasDim> K = llt_solve(llt, A * Sig).transpose();
        mu = Motion::retract(mu, K * nu);
        Sig -= K * S * K.transpose();
        symmetrize(Sig);
      }
      if (Eigen::LLT<Covariance>(Sig).info() != Eigen::Success) break;  // keep the previous iterate
      const bool converged = l > 0 && kl_divergence(lin, lin_cov, mu, Sig) < config_.ipl_tolerance;
      lin = mu;
      lin_cov = Sig;
      if (converged) break;
    }
    mean_out = lin;
    cov_out = lin_cov;
  }

  Motion motion_;
  Meas model_;
  RbpfConfig config_;
  bool use_mean_ = false;  ///< one particle and RbpfConfig::single_particle "mean": sample() gives the mean
  double scale_ = 1.0;     ///< RbpfConfig::proposal_scale
  Births births_ = Births::kNever;  ///< RbpfConfig::proposal_births
};

}  // namespace glmbslam::backend
