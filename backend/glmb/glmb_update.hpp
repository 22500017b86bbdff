#pragma once
// δ-GLMB joint prediction/update of one landmark map at a given sensor pose (paper 000 Eq. 11–16, with the
// Gibbs sampler of Vo, Vo & Hoang 2017; digest 0.2).
//
// Per call:
//  1. Active tracks: those with p_D > 0 or p_S < 1 at the pose (a distance test rejects the rest at once).
//     Inactive tracks have η(dead) = 0, η(missed) = 1, η(detected) = 0 and are copied through untouched.
//  2. For every active track and every birth candidate: the innovation, gain and updated covariance are
//     computed once; for every measurement passing the χ² gate the updated mean and the log likelihood are
//     computed once (EKF update cached per track–measurement pair, shared by all hypotheses).
//  3. Per parent hypothesis h: the sparse η table (rows: its active tracks, then the births), T_h ∝ √ω_h
//     Gibbs sweeps, distinct solutions → children (parent, ids chosen by its rows), log weight log ω_h +
//     Σ_i log η_i(γ_i); the parent's out-of-view ids are stored once per parent, not per child.
//  4. log Ĝ = log Σ children weights (the δ-GLMB normaliser, = g(Z|Z_{1:k−1}, x_{0:k}) / (e^{−λ} Π κ)).
//  5. Duplicate children merged, normalised, pruned (relative weight < prune_threshold), capped at H_max,
//     renormalised; the track table is compacted to the referenced tracks.
//  6. Far tracks in every hypothesis are frozen, frozen tracks near the sensor thawed (frozen_tracks.hpp).
//  7. Birth candidates for the next update from this scan (adaptive birth): r_B = birth_prob_explained for
//     a measurement that gated with an active track, birth_prob_unexplained otherwise.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "backend/glmb/frozen_tracks.hpp"
#include "backend/glmb/gate_bound.hpp"
#include "backend/glmb/gibbs_sampler.hpp"
#include "backend/glmb/glmb_config.hpp"
#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/llt_solve.hpp"
#include "backend/glmb/measurement_check.hpp"
#include "core/error.hpp"
#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

/// Innovation quantities of one landmark Gaussian at one pose, independent of the measurement.
template <class Meas>
struct Innovation {
  typename Meas::Measurement zhat;
  typename Meas::LandmarkJacobian H_m;
  Eigen::LLT<typename Meas::MeasurementCovariance> S_llt;
  Eigen::Matrix<double, Meas::kLandmarkDim, Meas::kMeasDim> K;  ///< P H_mᵀ S⁻¹
  typename Meas::LandmarkCovariance P_updated;                  ///< Joseph form (I−KH)P(I−KH)ᵀ + KRKᵀ
  double log_norm = 0.0;                                        ///< −½(d log 2π + log|S|)
  typename Meas::Measurement diag_S;  ///< diag(S), for the gate bound (gate_bound.hpp)
  bool valid = false;

  void compute(const Meas& model, const typename Meas::Pose& x, const typename Meas::Landmark& mean,
               const typename Meas::LandmarkCovariance& P) {
    zhat = model.linearize(x, mean, nullptr, &H_m);
    typename Meas::MeasurementCovariance S = H_m * P * H_m.transpose() + model.noise();
    S_llt.compute(S);
    valid = S_llt.info() == Eigen::Success;
    if (!valid) return;
    diag_S = S.diagonal();
    K = llt_solve(S_llt, H_m * P).transpose();
    const typename Meas::LandmarkCovariance I_KH = Meas::LandmarkCovariance::Identity() - K * H_m;
    P_updated = I_KH * P * I_KH.transpose() + K * model.noise() * K.transpose();
    symmetrize(P_updated);
    double log_det = 0.0;
    for (int i = 0; i < Meas::kMeasDim; ++i) log_det += std::log(S_llt.matrixLLT()(i, i));
    log_norm = -0.5 * (Meas::kMeasDim * std::log(2.0 * M_PI)) - log_det;
  }

  /// Gated EKF update with measurement z: returns false if z is outside the gate; otherwise the updated mean
  /// and log N(z; ẑ, S).
  bool update(const Meas& model, const typename Meas::Landmark& mean, const typename Meas::Measurement& z,
              double gate, typename Meas::Landmark* mean_out, double* log_likelihood) const {
    if (!valid) return false;
    const typename Meas::Measurement nu = model.residual(z, zhat);
    if (fails_gate_on_diagonal(nu, diag_S, gate)) return false;
    const double d2 = S_llt.matrixL().solve(nu).squaredNorm();
    if (!(d2 <= gate)) return false;
    *mean_out = mean + K * nu;
    *log_likelihood = log_norm - 0.5 * d2;
    return true;
  }
};

struct GlmbUpdateStats {
  double log_normalizer = 0.0;  ///< log Ĝ: the sum of the sampled children's weights
  /// log Ĝ without the sampler: Σ_h w_h Π_rows Σ_entries η (each row's total mass; exact when no two rows of
  /// a hypothesis gate with the same measurement, an upper bound otherwise). Free of the Gibbs sampler's
  /// coverage noise, which for hundreds of rows reaches several nats.
  double log_normalizer_factorized = 0.0;
  int active_tracks = 0;
  int hypotheses = 0;
  int tracks = 0;
};

template <class Meas>
class GlmbUpdater {
 public:
  using Pose = typename Meas::Pose;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = GlmbMap<Meas>;
  using TrackType = Track<Meas>;

  GlmbUpdater(const Meas& model, const GlmbConfig& config) : model_(model), config_(config) {}
  const GlmbConfig& config() const { return config_; }
  const Meas& model() const { return model_; }

  /// Throws InputError if a measurement is not finite.
  void validate(const MeasurementSet& Z, int step) const { validate_measurement_set(model_, Z, step); }

  /// prior → posterior at pose x with the measurement set Z of time step `step`.
  GlmbUpdateStats update(const Map& prior, const Pose& x, const MeasurementSet& Z, int step,
                         RandomStream& rng, Map& posterior) const {
    validate(Z, step);
    Workspace& ws = workspace();
    const int M = static_cast<int>(Z.size());
    const int n_old = static_cast<int>(prior.tracks.size());
    const int n_birth = static_cast<int>(prior.births.size());
    const double gate = config_.gate_threshold;

    // 1. active tracks
    prior.find_active(model_, x, config_.fov_margin, ws.active, &ws.track_pd);
    // 2. row sources: active tracks (source index = track index order) and births; cached EKF pairs
    ws.source_of_track.assign(n_old, -1);
    ws.extra.clear();
    ws.entry_column.clear();
    ws.entry_log_eta.clear();
    ws.entry_id.clear();
    ws.source_begin.clear();
    ws.explained.assign(M, 0);
    Innovation<Meas> inn;
    typename Meas::Landmark m_upd;
    int num_active = 0;
    using Appearance = typename AppearanceOf<Meas>::Type;
    auto add_source = [&](const Label& label, const typename Meas::Landmark& mean,
                          const typename Meas::LandmarkCovariance& P, const Appearance& appearance,
                          double log_exist, double log_not_exist, int missed_id, bool is_birth, double pd) {
      ws.source_begin.push_back(static_cast<int>(ws.entry_column.size()));
      if (log_not_exist > kLogZero) push_entry(ws, AssociationTable::kDead, log_not_exist, -1);
      if (pd < 1.0) push_entry(ws, AssociationTable::kMissed, log_exist + std::log1p(-pd), missed_id);
      if (pd <= 0.0) return;
      inn.compute(model_, x, mean, P);
      const double log_pd = std::log(pd);
      for (int j = 0; j < M; ++j) {
        double log_lik;
        if (!inn.update(model_, mean, Z[j], gate, &m_upd, &log_lik)) continue;
        if (!is_birth) ws.explained[j] = 1;
        const int id = n_old + static_cast<int>(ws.extra.size());
        ws.extra.push_back(TrackType{label, m_upd, inn.P_updated, appearance});
        if constexpr (AppearanceOf<Meas>::kEnabled) {
          if (model_.uses_appearance()) {
            log_lik += model_.log_appearance_ratio(appearance, j);
            ws.extra.back().appearance = model_.measurement_appearance(j);  // the latest look of the landmark
          }
        }
        push_entry(ws, j + 1, log_exist + log_pd + log_lik - model_.log_clutter_intensity(Z[j]), id);
      }
    };
    for (int t = 0; t < n_old; ++t) {
      if (!ws.active[t]) continue;
      const auto& tr = prior.tracks[t];
      const double ps = model_.survival_probability(x, tr.mean);
      ws.source_of_track[t] = num_active++;
      add_source(tr.label, tr.mean, tr.cov, tr.appearance, std::log(ps),
                 ps < 1.0 ? std::log1p(-ps) : kLogZero, t, false, ws.track_pd[t]);
    }
    // birth prior tracks get ids after the pair tracks created so far; give them their own slots first
    ws.birth_prior_id.resize(n_birth);
    for (int b = 0; b < n_birth; ++b) {
      const auto& bc = prior.births[b];
      ws.birth_prior_id[b] = n_old + static_cast<int>(ws.extra.size());
      ws.extra.push_back(TrackType{bc.label, bc.mean, bc.cov, bc.appearance});
    }
    const int birth_pair_first =
        n_old + static_cast<int>(ws.extra.size());  // births' updated pairs from here
    // A birth that gates with no measurement can only be "not born" or "born and missed"; the second has a
    // relative weight of about r_B (1 − p_D) (below the pruning threshold for the paper's r_B), so such
    // births are marginalised out of the sampler: every child gets the factor η(−1) + η(0) and the birth is
    // dropped.
    ws.birth_in_sampler.assign(n_birth, 1);
    double log_birth_factor = 0.0;
    for (int b = 0; b < n_birth; ++b) {
      const auto& bc = prior.births[b];
      const double log_r = bc.log_existence;
      const double log_1mr = log_r < 0.0 ? std::log(-std::expm1(log_r)) : kLogZero;
      const int first = static_cast<int>(ws.entry_column.size());
      add_source(bc.label, bc.mean, bc.cov, bc.appearance, log_r, log_1mr, ws.birth_prior_id[b], true,
                 model_.detection_probability(x, bc.mean));
      bool detectable = false;
      for (int e = first; e < static_cast<int>(ws.entry_column.size()); ++e)
        detectable |= ws.entry_column[e] > 0;
      if (!detectable) {
        ws.birth_in_sampler[b] = 0;
        double f = kLogZero;
        for (int e = first; e < static_cast<int>(ws.entry_column.size()); ++e)
          f = log_add(f, ws.entry_log_eta[e]);
        log_birth_factor += f;
      }
    }
    ws.source_begin.push_back(static_cast<int>(ws.entry_column.size()));
    // the sampler's rows, prepared once (η relative to the row maximum) and shared by every parent
    const int n_sources = num_active + n_birth;
    ws.sources.reset(M);
    for (int s = 0; s < n_sources; ++s) {
      for (int e = ws.source_begin[s]; e < ws.source_begin[s + 1]; ++e)
        ws.sources.add(ws.entry_column[e], ws.entry_log_eta[e]);
      ws.sources.end_row();
    }

    // total mass of each row (log Σ_e η_e), for the factorised normaliser
    ws.source_mass.resize(static_cast<std::size_t>(n_sources));
    for (int s = 0; s < n_sources; ++s) {
      ws.source_mass[static_cast<std::size_t>(s)] = log_sum_exp(
          ws.entry_log_eta.begin() + ws.source_begin[s], ws.entry_log_eta.begin() + ws.source_begin[s + 1]);
    }
    ws.parent_mass.clear();

    // 3. per parent hypothesis: Gibbs sampling of the children. A child is stored as (parent, the ids its
    // rows chose); the parent's out-of-view ids, identical in all its children, are kept once per parent,
    // so building, hashing and comparing a child costs O(rows), not O(|I_h|).
    ws.child_ids.clear();
    ws.child_begin.clear();
    ws.child_log_w.clear();
    ws.child_parent.clear();
    ws.parent_inactive.clear();
    ws.parent_inactive_begin.clear();
    const int n_parents = static_cast<int>(prior.hypotheses.size());
    double sum_sqrt = 0.0;
    for (const auto& h : prior.hypotheses) sum_sqrt += std::exp(0.5 * h.log_weight);
    // a parent's hash (used in step 5): the wrapping sum of per-id hashes over its out-of-view ids plus
    // their count (independent additions that pipeline, unlike a chained hash); computed while the ids are
    // collected. The per-id hashes depend only on the id, so the table is kept between calls.
    for (int t = static_cast<int>(ws.id_hash.size()); t < n_old; ++t)
      ws.id_hash.push_back(splitmix64(static_cast<std::uint64_t>(t) + 0x2545f4914f6cdd1dULL));
    ws.parent_hash.resize(n_parents);
    ws.birth_rows.clear();
    for (int b = 0; b < n_birth; ++b)
      if (ws.birth_in_sampler[b]) ws.birth_rows.push_back(num_active + b);
    for (int p = 0; p < n_parents; ++p) {
      const Hypothesis& h = prior.hypotheses[p];
      const std::size_t n_h = h.tracks.size();
      const std::size_t inactive_first = ws.parent_inactive.size();
      ws.parent_inactive_begin.push_back(static_cast<int>(inactive_first));
      ws.parent_inactive.resize(inactive_first + n_h);
      ws.row_source.resize(n_h + ws.birth_rows.size());
      std::uint32_t* inactive_out = ws.parent_inactive.data() + inactive_first;
      int* row_out = ws.row_source.data();
      const int* const source_of_track = ws.source_of_track.data();
      const std::uint64_t* const id_hash = ws.id_hash.data();
      std::uint64_t hsh = 0;
      for (const std::uint32_t t : h.tracks) {  // branch-free: both outputs written, one cursor advances
        const int s = source_of_track[t];
        const bool in_view = s >= 0;
        *row_out = s;
        row_out += in_view;
        *inactive_out = t;  // out of view: copied through to every child
        inactive_out += !in_view;
        hsh += id_hash[t] & (in_view ? 0ULL : ~0ULL);
      }
      const std::size_t n_inactive =
          static_cast<std::size_t>(inactive_out - ws.parent_inactive.data()) - inactive_first;
      ws.parent_hash[p] = static_cast<std::uint64_t>(n_inactive) + hsh;
      ws.parent_inactive.resize(inactive_first + n_inactive);
      row_out = std::copy(ws.birth_rows.begin(), ws.birth_rows.end(), row_out);
      ws.row_source.resize(static_cast<std::size_t>(row_out - ws.row_source.data()));
      const int rows = static_cast<int>(ws.row_source.size());
      {
        double mass = h.log_weight + log_birth_factor;
        for (int i = 0; i < rows; ++i) mass += ws.source_mass[static_cast<std::size_t>(ws.row_source[i])];
        ws.parent_mass.push_back(mass);
      }
      const int sweeps =
          rows == 0 ? 0
                    : std::max(1, static_cast<int>(std::lround(config_.gibbs_samples *
                                                               std::exp(0.5 * h.log_weight) / sum_sqrt)));
      ws.samples.clear();
      const int count =
          gibbs_sample(ws.sources, ws.row_source.data(), rows, sweeps, rng, ws.gibbs, ws.samples, true);
      const int distinct = unique_solutions(ws.samples, rows, count);
      // The ids a child chooses come in four classes with increasing id ranges: missed tracks (< n_old),
      // updated track pairs, birth priors and updated birth pairs. Within each class they increase with the
      // row, so the child's sorted id list is the classes' concatenation (track rows give the first two,
      // birth rows the last two).
      const int track_rows = rows - static_cast<int>(ws.birth_rows.size());
      const int* const source_begin = ws.source_begin.data();
      const int* const entry_column = ws.entry_column.data();
      const double* const entry_log_eta = ws.entry_log_eta.data();
      const int* const entry_id = ws.entry_id.data();
      const int* const row_source = ws.row_source.data();
      for (int c = 0; c < distinct; ++c) {
        const int* gamma = ws.samples.data() + static_cast<std::size_t>(c) * rows;
        double log_w = h.log_weight + log_birth_factor;
        const std::size_t first = ws.child_ids.size();
        ws.child_ids.resize(first + static_cast<std::size_t>(rows));
        std::uint32_t* const ids = ws.child_ids.data() + first;
        int n_low = 0, n_high = 0;  // ids of the current row group below / at or above its split
        std::uint32_t* const high = ws.id_scratch.size() >= static_cast<std::size_t>(rows)
                                        ? ws.id_scratch.data()
                                        : (ws.id_scratch.resize(rows), ws.id_scratch.data());
        // row i's chosen entry: its log η joins log_w and its track id joins the child (the track's own index
        // when missed, an updated pair track ≥ n_old when detected, nothing when dead / not born)
        auto choose = [&](int i) {
          const int s = row_source[i];
          for (int e = source_begin[s]; e < source_begin[s + 1]; ++e) {
            if (entry_column[e] == gamma[i]) {
              log_w += entry_log_eta[e];
              return entry_id[e];
            }
          }
          log_w = kLogZero;
          return -2;
        };
        for (int i = 0; i < track_rows && log_w != kLogZero; ++i) {
          const int id = choose(i);
          if (id < 0) continue;
          if (id < n_old)
            ids[n_low++] = static_cast<std::uint32_t>(id);
          else
            high[n_high++] = static_cast<std::uint32_t>(id);
        }
        std::copy(high, high + n_high, ids + n_low);
        n_low += n_high;
        n_high = 0;
        for (int i = track_rows; i < rows && log_w != kLogZero; ++i) {
          const int id = choose(i);
          if (id < 0) continue;
          if (id < birth_pair_first)
            ids[n_low++] = static_cast<std::uint32_t>(id);
          else
            high[n_high++] = static_cast<std::uint32_t>(id);
        }
        if (log_w == kLogZero) {
          ws.child_ids.resize(first);
          continue;
        }
        std::copy(high, high + n_high, ids + n_low);
        ws.child_ids.resize(first + static_cast<std::size_t>(n_low + n_high));
        ws.child_begin.push_back(static_cast<int>(first));
        ws.child_log_w.push_back(log_w);
        ws.child_parent.push_back(p);
      }
    }
    const int n_children = static_cast<int>(ws.child_log_w.size());
    ws.child_begin.push_back(static_cast<int>(ws.child_ids.size()));
    ws.parent_inactive_begin.push_back(static_cast<int>(ws.parent_inactive.size()));

    GlmbUpdateStats stats;
    stats.active_tracks = num_active;
    // 4. normaliser
    stats.log_normalizer = log_sum_exp(ws.child_log_w);
    stats.log_normalizer_factorized = log_sum_exp(ws.parent_mass);

    // 5. merge duplicates (children with identical track-id sets), normalise, prune, cap.
    // Parents with identical out-of-view id lists form one class; two children are equal iff their parents
    // are in the same class and they chose the same ids.
    auto inactive_begin = [&](int p) { return ws.parent_inactive.begin() + ws.parent_inactive_begin[p]; };
    auto inactive_end = [&](int p) { return ws.parent_inactive.begin() + ws.parent_inactive_begin[p + 1]; };
    // (parent hashes: computed in step 3; equal hashes are confirmed by comparing the lists)
    ws.parent_order.resize(n_parents);
    std::iota(ws.parent_order.begin(), ws.parent_order.end(), 0);
    std::sort(ws.parent_order.begin(), ws.parent_order.end(), [&](int a, int b) {
      return ws.parent_hash[a] != ws.parent_hash[b] ? ws.parent_hash[a] < ws.parent_hash[b] : a < b;
    });
    ws.parent_class.assign(n_parents, -1);
    for (int k = 0; k < n_parents; ++k) {
      const int p = ws.parent_order[k];
      if (ws.parent_class[p] >= 0) continue;
      ws.parent_class[p] = p;
      for (int l = k + 1; l < n_parents && ws.parent_hash[ws.parent_order[l]] == ws.parent_hash[p]; ++l) {
        const int q = ws.parent_order[l];
        if (ws.parent_class[q] < 0 &&
            std::equal(inactive_begin(p), inactive_end(p), inactive_begin(q), inactive_end(q)))
          ws.parent_class[q] = p;
      }
    }
    ws.child_hash.resize(n_children);
    for (int c = 0; c < n_children; ++c) {
      const int cls = ws.parent_class[ws.child_parent[c]];
      std::uint64_t hsh =
          ws.parent_hash[cls] ^ static_cast<std::uint64_t>(ws.child_begin[c + 1] - ws.child_begin[c]);
      for (int k = ws.child_begin[c]; k < ws.child_begin[c + 1]; ++k) hsh = splitmix64(hsh ^ ws.child_ids[k]);
      ws.child_hash[c] = splitmix64(hsh ^ static_cast<std::uint64_t>(cls));
    }
    ws.order.resize(n_children);
    std::iota(ws.order.begin(), ws.order.end(), 0);
    auto ids_less = [&](int a, int b) {  // -1, 0, 1 on (class, chosen ids)
      const int ca = ws.parent_class[ws.child_parent[a]], cb = ws.parent_class[ws.child_parent[b]];
      if (ca != cb) return ca < cb ? -1 : 1;
      const auto ab = ws.child_ids.begin() + ws.child_begin[a],
                 ae = ws.child_ids.begin() + ws.child_begin[a + 1];
      const auto bb = ws.child_ids.begin() + ws.child_begin[b],
                 be = ws.child_ids.begin() + ws.child_begin[b + 1];
      if (std::lexicographical_compare(ab, ae, bb, be)) return -1;
      if (std::lexicographical_compare(bb, be, ab, ae)) return 1;
      return 0;
    };
    std::sort(ws.order.begin(), ws.order.end(), [&](int a, int b) {
      if (ws.child_hash[a] != ws.child_hash[b]) return ws.child_hash[a] < ws.child_hash[b];
      const int cmp = ids_less(a, b);
      return cmp != 0 ? cmp < 0 : a < b;
    });
    ws.merged.clear();
    for (int k = 0; k < n_children; ++k) {
      const int c = ws.order[k];
      if (!ws.merged.empty() && ws.child_hash[ws.merged.back().first] == ws.child_hash[c] &&
          ids_less(ws.merged.back().first, c) == 0) {
        ws.merged.back().second = log_add(ws.merged.back().second, ws.child_log_w[c]);
      } else {
        ws.merged.emplace_back(c, ws.child_log_w[c]);
      }
    }
    std::sort(ws.merged.begin(), ws.merged.end(), [](const auto& a, const auto& b) {
      return a.second != b.second ? a.second > b.second : a.first < b.first;
    });
    const double log_prune = std::log(config_.prune_threshold);
    std::size_t keep = 0;
    for (; keep < ws.merged.size() && static_cast<int>(keep) < config_.max_hypotheses; ++keep) {
      if (keep > 0 && ws.merged[keep].second - stats.log_normalizer < log_prune) break;
    }
    ws.merged.resize(keep);
    double log_kept = kLogZero;
    for (const auto& mc : ws.merged) log_kept = log_add(log_kept, mc.second);

    // compaction: new indices in increasing id order, so sorted id lists stay sorted
    const int n_ids = n_old + static_cast<int>(ws.extra.size());
    // (the out-of-view ids of a class — parents with identical lists — are marked and remapped once)
    ws.new_index.assign(n_ids, -1);
    ws.class_remap_begin.assign(n_parents, -1);
    for (const auto& mc : ws.merged) {
      const int cls = ws.parent_class[ws.child_parent[mc.first]];
      if (ws.class_remap_begin[cls] == -1) {
        ws.class_remap_begin[cls] = -2;  // marked
        for (auto it = inactive_begin(cls); it != inactive_end(cls); ++it) ws.new_index[*it] = 0;
      }
      for (int k = ws.child_begin[mc.first]; k < ws.child_begin[mc.first + 1]; ++k)
        ws.new_index[ws.child_ids[k]] = 0;
    }
    posterior.tracks.clear();
    posterior.tracks.reserve(static_cast<std::size_t>(
        std::count_if(ws.new_index.begin(), ws.new_index.end(), [](int v) { return v >= 0; })));
    for (int id = 0; id < n_ids; ++id) {
      if (ws.new_index[id] < 0) continue;
      ws.new_index[id] = static_cast<int>(posterior.tracks.size());
      posterior.tracks.push_back(id < n_old ? prior.tracks[id] : ws.extra[id - n_old]);
    }
    ws.class_remap.clear();
    for (const auto& mc : ws.merged) {
      const int cls = ws.parent_class[ws.child_parent[mc.first]];
      if (ws.class_remap_begin[cls] >= 0) continue;
      ws.class_remap_begin[cls] = static_cast<int>(ws.class_remap.size());
      for (auto it = inactive_begin(cls); it != inactive_end(cls); ++it)
        ws.class_remap.push_back(static_cast<std::uint32_t>(ws.new_index[*it]));
    }
    posterior.hypotheses.resize(ws.merged.size());
    for (std::size_t k = 0; k < ws.merged.size(); ++k) {
      const auto& mc = ws.merged[k];
      const int cls = ws.parent_class[ws.child_parent[mc.first]];
      Hypothesis& h = posterior.hypotheses[k];
      h.log_weight = mc.second - log_kept;
      const std::uint32_t* in = ws.class_remap.data() + ws.class_remap_begin[cls];
      const std::uint32_t* const in_end = in + (inactive_end(cls) - inactive_begin(cls));
      const int c_begin = ws.child_begin[mc.first], c_end = ws.child_begin[mc.first + 1];
      h.tracks.resize(static_cast<std::size_t>((in_end - in) + (c_end - c_begin)));
      // the union of two sorted id lists (disjoint: out-of-view ids and chosen ids), both remapped
      // monotonically: each of the few chosen ids is inserted into the long out-of-view run
      std::uint32_t* out = h.tracks.data();
      for (int c = c_begin; c < c_end; ++c) {
        const auto id = static_cast<std::uint32_t>(ws.new_index[ws.child_ids[c]]);
        const std::uint32_t* const pos = std::lower_bound(in, in_end, id);
        out = std::copy(in, pos, out);
        *out++ = id;
        in = pos;
      }
      std::copy(in, in_end, out);
    }
    if (posterior.hypotheses.empty()) posterior.hypotheses.push_back(Hypothesis{0.0, {}});
    posterior.frozen = prior.frozen;
    posterior.frozen_count = prior.frozen_count;
    freeze_and_thaw(model_, config_, Meas::position(x), posterior, ws.scratch);

    // 7. birth candidates for the next update
    posterior.births.clear();
    if (config_.births) {
      const double log_unexplained = std::log(config_.birth_prob_unexplained);
      const double log_explained = std::log(config_.birth_prob_explained);
      for (int j = 0; j < M; ++j) {
        BirthCandidate<Meas> bc;
        bc.label = Label{step + 1, j};
        model_.initialize(x, Z[j], &bc.mean, &bc.cov);
        bc.log_existence = ws.explained[j] ? log_explained : log_unexplained;
        if constexpr (AppearanceOf<Meas>::kEnabled) bc.appearance = model_.measurement_appearance(j);
        posterior.births.push_back(bc);
      }
    }
    stats.hypotheses = static_cast<int>(posterior.hypotheses.size());
    stats.tracks = static_cast<int>(posterior.total_tracks());
    return stats;
  }

 private:
  struct Workspace {
    std::vector<char> active;
    std::vector<int> source_of_track, source_begin, entry_column, entry_id, birth_prior_id, row_source,
        birth_rows;
    std::vector<double> entry_log_eta, track_pd;
    std::vector<double> source_mass, parent_mass;  ///< factorised normaliser: per row, per parent
    std::vector<char> explained, birth_in_sampler;
    std::vector<TrackType, Eigen::aligned_allocator<TrackType>> extra;
    AssociationTable sources;  ///< one row per source (active track or birth)
    GibbsWorkspace gibbs;
    std::vector<int> samples;
    std::vector<std::uint32_t> child_ids, id_scratch;
    std::vector<int> child_begin, order, new_index, child_parent;
    std::vector<std::uint32_t> parent_inactive;
    std::vector<int> parent_inactive_begin, parent_order, parent_class, class_remap_begin;
    std::vector<std::uint32_t> class_remap;
    std::vector<std::uint64_t> parent_hash, id_hash;
    std::vector<int> scratch;
    std::vector<double> child_log_w;
    std::vector<std::uint64_t> child_hash;
    std::vector<std::pair<int, double>> merged;
  };
  static Workspace& workspace() {
    static thread_local Workspace ws;
    return ws;
  }
  static void push_entry(Workspace& ws, int column, double log_eta, int id) {
    ws.entry_column.push_back(column);
    ws.entry_log_eta.push_back(log_eta);
    ws.entry_id.push_back(id);
  }

  Meas model_;
  GlmbConfig config_;
};

}  // namespace glmbslam::backend
