#pragma once
// The LMB-SLAM map update at a given sensor pose: the δ-GLMB joint prediction/update of an LMB prior with
// the Gibbs sampler (the LMB is one δ-GLMB "parent" whose every label is an uncertain Bernoulli), then the
// LMB approximation of the sampled δ-GLMB posterior (lmb_map.hpp).
//
// Per call:
//  1. Active Bernoullis: p_D > 0 or p_S < 1 at the pose (evaluated at the label's highest-weight component);
//     the others are copied through unchanged.
//  2. One sampler row per active Bernoulli (existence r, GM density Σ_c w_c N(m_c, P_c)) and per birth
//     candidate (r_B, one Gaussian), η as in the joint prediction/update (Vo, Vo & Hoang 2017):
//       dead / not born   1 − r p_S
//       missed            r p_S (1 − p_D)
//       detected by z_j   r p_S p_D Σ_c w_c N(z_j; ẑ_c, S_c) / κ(z_j)   (components inside the χ² gate)
//     (p_S = 1 for a birth); each gated component's EKF update is computed once.
//  3. gibbs_samples sweeps, distinct solutions γ with weights Π_i η_i(γ_i); log Ĝ = log Σ_γ Π_i η_i(γ_i)
//     (the δ-GLMB normaliser of this one-parent prior: the particle's weight factor).
//  4. The LMB approximation: per row, the normalised mass of each chosen entry over the solutions gives
//     r' = Σ_{entries ≠ dead} mass and the density Σ_entries mass · (that entry's density) / r'; components
//     reduced (LmbConfig::component_prune, max_components); Bernoullis with r' < existence_threshold removed.
//  5. Birth candidates for the next update from this scan (as in the δ-GLMB update: r_B =
//     birth_prob_explained for a measurement an active Bernoulli gated, birth_prob_unexplained otherwise).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "backend/glmb/gibbs_sampler.hpp"
#include "backend/glmb/glmb_config.hpp"
#include "backend/glmb/glmb_update.hpp"
#include "backend/glmb/measurement_check.hpp"
#include "backend/lmb/lmb_config.hpp"
#include "backend/lmb/lmb_map.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

struct LmbUpdateStats {
  double log_normalizer = kLogZero;             ///< log Ĝ over the distinct sampled solutions
  double log_normalizer_factorized = kLogZero;  ///< Σ_rows log Σ_entries η (no sampler noise)
  int active_tracks = 0;
  int solutions = 0;  ///< distinct association maps
  int tracks = 0;     ///< Bernoullis of the posterior
};

template <class Meas>
class LmbUpdater {
 public:
  using Pose = typename Meas::Pose;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Map = LmbMap<Meas>;
  using Component = LmbComponent<Meas>;
  using ComponentList = std::vector<Component, Eigen::aligned_allocator<Component>>;
  using Appearance = typename AppearanceOf<Meas>::Type;

  LmbUpdater(const Meas& model, const GlmbConfig& glmb, const LmbConfig& lmb)
      : model_(model), glmb_(glmb), lmb_(lmb) {}
  const Meas& model() const { return model_; }

  /// Throws InputError if a measurement is not finite.
  void validate(const MeasurementSet& Z, int step) const { validate_measurement_set(model_, Z, step); }

  /// prior → posterior at pose x with the measurement set Z of time step `step`.
  LmbUpdateStats update(const Map& prior, const Pose& x, const MeasurementSet& Z, int step, RandomStream& rng,
                        Map& posterior) const {
    validate(Z, step);
    Workspace& ws = workspace();
    const int M = static_cast<int>(Z.size());
    ws.reset(M);
    LmbUpdateStats stats;
    posterior.tracks.clear();
    posterior.components.clear();
    // 1.–2. rows
    const auto p = Meas::position(x);
    const double radius = model_.query_radius() + glmb_.fov_margin;
    for (std::size_t t = 0; t < prior.tracks.size(); ++t) {
      const LmbTrack<Meas>& tr = prior.tracks[t];
      const Component& dom = prior.dominant(t);
      bool active = false;
      double pd = 0.0, ps = 1.0;
      if ((Meas::landmark_position(dom.mean) - p).squaredNorm() <= radius * radius) {
        pd = model_.detection_probability(x, dom.mean);
        ps = model_.survival_probability(x, dom.mean);
        active = pd > 0.0 || ps < 1.0;
      }
      if (!active) {  // copied through
        ws.copy.assign(prior.components.begin() + tr.first, prior.components.begin() + tr.first + tr.count);
        posterior.add_track(tr.label, tr.existence, ws.copy, tr.appearance);
        continue;
      }
      ++stats.active_tracks;
      add_row(ws, x, Z, tr.label, prior.components.data() + tr.first, tr.count, tr.existence * ps, pd,
              tr.appearance, false);
    }
    for (const auto& bc : prior.births) {
      const Component c{1.0, bc.mean, bc.cov};
      add_row(ws, x, Z, bc.label, &c, 1, std::exp(bc.log_existence), model_.detection_probability(x, bc.mean),
              bc.appearance, true);
    }
    const int rows = ws.table.rows();
    // 3. sampling
    ws.samples.clear();
    const int count = gibbs_sample(ws.table, rows == 0 ? 0 : glmb_.gibbs_samples, rng, ws.gibbs, ws.samples);
    const int distinct = unique_solutions(ws.samples, rows, count);
    ws.solution_log_w.resize(static_cast<std::size_t>(distinct));
    for (int s = 0; s < distinct; ++s)
      ws.solution_log_w[static_cast<std::size_t>(s)] = ws.table.log_weight(
          ws.samples.data() + static_cast<std::size_t>(s) * static_cast<std::size_t>(rows));
    stats.solutions = distinct;
    stats.log_normalizer = log_sum_exp(ws.solution_log_w);
    stats.log_normalizer_factorized = 0.0;
    for (int i = 0; i < rows; ++i) {
      double row = kLogZero;
      for (int e = ws.table.row_begin(i); e < ws.table.row_end(i); ++e)
        row = log_add(row, ws.table.log_eta(e));
      stats.log_normalizer_factorized += row;
    }
    // 4. entry masses and the LMB approximation
    ws.mass.assign(ws.entry_first.size(), 0.0);
    if (stats.log_normalizer > kLogZero) {
      for (int s = 0; s < distinct; ++s) {
        const double w = std::exp(ws.solution_log_w[static_cast<std::size_t>(s)] - stats.log_normalizer);
        const int* gamma = ws.samples.data() + static_cast<std::size_t>(s) * static_cast<std::size_t>(rows);
        for (int i = 0; i < rows; ++i) {
          for (int e = ws.table.row_begin(i); e < ws.table.row_end(i); ++e) {
            if (ws.table.column(e) == gamma[i]) {
              ws.mass[static_cast<std::size_t>(e)] += w;
              break;
            }
          }
        }
      }
    }
    for (int i = 0; i < rows; ++i) {
      double r = 0.0, best_mass = -1.0;
      const Appearance* appearance = &ws.row_appearance[static_cast<std::size_t>(i)];
      ws.copy.clear();
      for (int e = ws.table.row_begin(i); e < ws.table.row_end(i); ++e) {
        const double m = ws.mass[static_cast<std::size_t>(e)];
        if (ws.table.column(e) == AssociationTable::kDead || m <= 0.0) continue;
        r += m;
        for (int c = ws.entry_first[static_cast<std::size_t>(e)];
             c < ws.entry_first[static_cast<std::size_t>(e) + 1]; ++c) {
          ws.copy.push_back(ws.entry_components[static_cast<std::size_t>(c)]);
          ws.copy.back().weight *= m;
        }
        if (m > best_mass) {
          best_mass = m;
          if (ws.table.column(e) > 0)
            appearance = &ws.measurement_appearance[static_cast<std::size_t>(ws.table.column(e) - 1)];
        }
      }
      r = std::min(1.0, r);
      if (ws.copy.empty() || r < lmb_.existence_threshold) continue;
      reduce_components<Meas>(ws.copy, lmb_.component_prune, lmb_.max_components);
      posterior.add_track(ws.row_label[static_cast<std::size_t>(i)], r, ws.copy, *appearance);
    }
    // 5. births for the next update
    posterior.births.clear();
    if (glmb_.births) {
      const double log_unexplained = std::log(glmb_.birth_prob_unexplained);
      const double log_explained = std::log(glmb_.birth_prob_explained);
      for (int j = 0; j < M; ++j) {
        BirthCandidate<Meas> bc;
        bc.label = Label{step + 1, j};
        model_.initialize(x, Z[static_cast<std::size_t>(j)], &bc.mean, &bc.cov);
        bc.log_existence = ws.explained[static_cast<std::size_t>(j)] ? log_explained : log_unexplained;
        if constexpr (AppearanceOf<Meas>::kEnabled) bc.appearance = model_.measurement_appearance(j);
        posterior.births.push_back(bc);
      }
    }
    stats.tracks = static_cast<int>(posterior.tracks.size());
    return stats;
  }

 private:
  struct Workspace {
    AssociationTable table;
    GibbsWorkspace gibbs;
    std::vector<int> samples;
    std::vector<double> solution_log_w, mass;
    std::vector<int> entry_first;  ///< per table entry e: its components [entry_first[e], entry_first[e+1])
    ComponentList entry_components, copy;
    std::vector<Label> row_label;
    std::vector<Appearance> row_appearance, measurement_appearance;
    std::vector<char> explained;
    std::vector<Innovation<Meas>, Eigen::aligned_allocator<Innovation<Meas>>> innovations;
    void reset(int M) {
      table.reset(M);
      entry_first.assign(1, 0);
      entry_components.clear();
      row_label.clear();
      row_appearance.clear();
      measurement_appearance.assign(static_cast<std::size_t>(M), Appearance{});
      explained.assign(static_cast<std::size_t>(M), 0);
    }
    /// Closes entry e: its components are those added since the previous entry.
    void end_entry() { entry_first.push_back(static_cast<int>(entry_components.size())); }
  };
  static Workspace& workspace() {
    static thread_local Workspace ws;
    return ws;
  }

  /// One sampler row for a Bernoulli that exists (after prediction) with probability r_pred.
  void add_row(Workspace& ws, const Pose& x, const MeasurementSet& Z, const Label& label,
               const Component* comps, int n_comps, double r_pred, double pd, const Appearance& appearance,
               bool is_birth) const {
    ws.row_label.push_back(label);
    ws.row_appearance.push_back(appearance);
    r_pred = std::min(r_pred, 1.0 - 1e-12);  // keeps the "dead" entry: a row is never empty
    const double log_r = std::log(r_pred);
    {
      ws.table.add(AssociationTable::kDead, std::log1p(-r_pred));
      ws.end_entry();
    }
    if (pd < 1.0) {
      ws.table.add(AssociationTable::kMissed, log_r + std::log1p(-pd));
      ws.entry_components.insert(ws.entry_components.end(), comps, comps + n_comps);
      ws.end_entry();
    }
    if (pd > 0.0) {
      const double log_pd = std::log(pd);
      ws.innovations.resize(static_cast<std::size_t>(n_comps));
      for (int c = 0; c < n_comps; ++c) ws_innovation(c).compute(model_, x, comps[c].mean, comps[c].cov);
      Component upd;
      for (int j = 0; j < static_cast<int>(Z.size()); ++j) {
        const std::size_t first = ws.entry_components.size();
        double log_sum = kLogZero;
        for (int c = 0; c < n_comps; ++c) {
          double log_lik;
          if (!ws_innovation(c).update(model_, comps[c].mean, Z[static_cast<std::size_t>(j)],
                                       glmb_.gate_threshold, &upd.mean, &log_lik))
            continue;
          if constexpr (AppearanceOf<Meas>::kEnabled) {
            if (model_.uses_appearance()) log_lik += model_.log_appearance_ratio(appearance, j);
          }
          upd.cov = ws_innovation(c).P_updated;
          const double log_q = std::log(comps[c].weight) + log_lik;
          upd.weight = log_q;  // log for now, normalised below
          ws.entry_components.push_back(upd);
          log_sum = log_add(log_sum, log_q);
        }
        if (ws.entry_components.size() == first) continue;
        for (std::size_t c = first; c < ws.entry_components.size(); ++c)
          ws.entry_components[c].weight = std::exp(ws.entry_components[c].weight - log_sum);
        if (!is_birth) ws.explained[static_cast<std::size_t>(j)] = 1;
        if constexpr (AppearanceOf<Meas>::kEnabled) {
          if (model_.uses_appearance())
            ws.measurement_appearance[static_cast<std::size_t>(j)] = model_.measurement_appearance(j);
        }
        ws.table.add(j + 1,
                     log_r + log_pd + log_sum - model_.log_clutter_intensity(Z[static_cast<std::size_t>(j)]));
        ws.end_entry();
      }
    }
    ws.table.end_row();
  }
  static Innovation<Meas>& ws_innovation(int c) {
    return workspace().innovations[static_cast<std::size_t>(c)];
  }

  Meas model_;
  GlmbConfig glmb_;
  LmbConfig lmb_;
};

}  // namespace glmbslam::backend
