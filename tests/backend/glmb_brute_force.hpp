#pragma once
// Brute-force reference for the δ-GLMB joint prediction/update (paper 000 Eq. 11–16), for any measurement
// model of the MeasurementModel concept (range_bearing_model.hpp): every parent hypothesis × every valid
// association γ (each row — a track in view or a birth candidate — dead/not born (−1), missed (0) or detected
// by one measurement j ≥ 1, no measurement used twice) is enumerated, its weight and its labelled EKF
// posteriors computed independently of glmb_update.hpp (plain S⁻¹ formulas, no gate, no sampler), and
// children with the same labelled densities merged. expect_matches_enumeration() compares a GlmbUpdater
// posterior with it.
//
// Per row with existence factor r (p_S for a track, r_B for a birth) and p_D at the prior mean:
//   η(−1) = 1 − r,   η(0) = r (1 − p_D),
//   η(j)  = r p_D N(z_j; ẑ, S) · e^{log_appearance_ratio(a, j)} / κ(z_j),   S = H P Hᵀ + R,
//   N(z; ẑ, S) = (2π)^{−d/2} |S|^{−1/2} exp(−½ νᵀS⁻¹ν)
// (the appearance factor only for models that declare one and switch it on). Tracks out of view (not in the
// field of view) are copied through unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "backend/glmb/appearance.hpp"
#include "backend/glmb/glmb_map.hpp"
#include "backend/glmb/glmb_update.hpp"
#include "core/log_math.hpp"

namespace glmbslam::backend::enumeration {

/// One labelled landmark density of an enumerated child.
template <class Model>
struct BruteLandmark {
  typename Model::Landmark mean;
  typename Model::LandmarkCovariance cov;
  typename AppearanceOf<Model>::Type appearance{};
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

template <class Model>
struct BruteChild {
  double log_w = kLogZero;                                  ///< unnormalised
  std::map<std::uint64_t, BruteLandmark<Model>> landmarks;  ///< label key → density
};

/// Every child of every parent hypothesis of `prior` at pose x with measurements z (Eq. 11–16).
template <class Model>
std::vector<BruteChild<Model>> brute_force(const Model& model, const GlmbMap<Model>& prior,
                                           const typename Model::Pose& x,
                                           const typename GlmbUpdater<Model>::MeasurementSet& z) {
  constexpr int d = Model::kMeasDim;
  using Landmark = typename Model::Landmark;
  using Cov = typename Model::LandmarkCovariance;
  using Appearance = typename AppearanceOf<Model>::Type;
  struct Row {
    Label label;
    Landmark mean;
    Cov P;
    Appearance appearance;
    double r;  // existence factor (p_S or r_B)
    EIGEN_MAKE_ALIGNED_OPERATOR_NEW
  };
  std::vector<BruteChild<Model>> out;
  const int M = static_cast<int>(z.size());
  for (const auto& h : prior.hypotheses) {
    std::vector<Row, Eigen::aligned_allocator<Row>> rows;
    std::map<std::uint64_t, BruteLandmark<Model>> passive;
    for (auto t : h.tracks) {
      const auto& tr = prior.tracks[t];
      if (model.in_field_of_view(x, tr.mean)) {
        rows.push_back({tr.label, tr.mean, tr.cov, tr.appearance, model.survival_probability(x, tr.mean)});
      } else {
        passive[tr.label.key()] = BruteLandmark<Model>{tr.mean, tr.cov, tr.appearance};
      }
    }
    for (const auto& b : prior.births)
      rows.push_back({b.label, b.mean, b.cov, b.appearance, std::exp(b.log_existence)});
    const int P = static_cast<int>(rows.size());
    std::vector<int> g(P, -1);
    while (true) {
      bool valid = true;
      for (int i = 0; i < P && valid; ++i)
        for (int k = i + 1; k < P; ++k)
          if (g[i] > 0 && g[i] == g[k]) valid = false;
      if (valid) {
        BruteChild<Model> c{h.log_weight, passive};
        for (int i = 0; i < P; ++i) {
          const Row& r = rows[i];
          const double pd = model.detection_probability(x, r.mean);
          if (g[i] == -1) {
            c.log_w += std::log(1 - r.r);
            continue;
          }
          if (g[i] == 0) {
            c.log_w += std::log(r.r * (1 - pd));
            c.landmarks[r.label.key()] = BruteLandmark<Model>{r.mean, r.P, r.appearance};
            continue;
          }
          const int j = g[i] - 1;
          typename Model::LandmarkJacobian H;
          const typename Model::Measurement zhat = model.linearize(x, r.mean, nullptr, &H);
          const typename Model::MeasurementCovariance S = H * r.P * H.transpose() + model.noise();
          const typename Model::MeasurementCovariance S_inv = S.inverse();
          const typename Model::Measurement nu = model.residual(z[j], zhat);
          const double log_lik =
              -0.5 * d * std::log(2 * M_PI) - 0.5 * std::log(S.determinant()) - 0.5 * nu.dot(S_inv * nu);
          c.log_w += std::log(r.r * pd) + log_lik - model.log_clutter_intensity(z[j]);
          const Eigen::Matrix<double, Model::kLandmarkDim, Model::kMeasDim> K = r.P * H.transpose() * S_inv;
          BruteLandmark<Model> updated{r.mean + K * nu, r.P - K * H * r.P, r.appearance};
          if constexpr (AppearanceOf<Model>::kEnabled) {
            if (model.uses_appearance()) {
              c.log_w += model.log_appearance_ratio(r.appearance, j);
              updated.appearance = model.measurement_appearance(j);
            }
          }
          c.landmarks[r.label.key()] = updated;
        }
        out.push_back(c);
      }
      int i = 0;
      while (i < P && ++g[i] > M) g[i++] = -1;
      if (i == P) break;
    }
  }
  return out;
}

/// Children of different parents with the same labelled densities merged (weights added).
template <class Model>
std::vector<BruteChild<Model>> merge_children(const std::vector<BruteChild<Model>>& children) {
  std::vector<BruteChild<Model>> merged;
  for (const auto& c : children) {
    bool done = false;
    for (auto& m : merged) {
      if (m.landmarks.size() != c.landmarks.size()) continue;
      bool same = true;
      for (const auto& [key, lm] : c.landmarks) {
        const auto it = m.landmarks.find(key);
        if (it == m.landmarks.end() || (it->second.mean - lm.mean).norm() > 1e-12) same = false;
      }
      if (same) {
        m.log_w = log_add(m.log_w, c.log_w);
        done = true;
        break;
      }
    }
    if (!done) merged.push_back(c);
  }
  return merged;
}

/// log Σ of the children's weights: the δ-GLMB normaliser log Ĝ.
template <class Model>
double log_normalizer(const std::vector<BruteChild<Model>>& children) {
  std::vector<double> logs;
  for (const auto& c : children) logs.push_back(c.log_w);
  return log_sum_exp(logs);
}

/// Smallest normalised log weight of the children.
template <class Model>
double min_log_weight(const std::vector<BruteChild<Model>>& children) {
  const double log_norm = log_normalizer(children);
  double min_w = 0.0;
  for (const auto& c : children) min_w = std::min(min_w, c.log_w - log_norm);
  return min_w;
}

/// The posterior of GlmbUpdater (pruning off) against the merged enumeration: normaliser, number of
/// hypotheses, weights summing to one, and for every enumerated child exactly one posterior hypothesis with
/// the same labels and means (and covariances, appearances), with the same normalised weight. `tol` applies
/// to log weights, means and covariances. Every child must have a normalised weight above `min_findable`
/// (so that the sampler's sweeps find it). Use with ASSERT_NO_FATAL_FAILURE.
template <class Model>
void expect_matches_enumeration(const GlmbMap<Model>& post, const GlmbUpdateStats& stats,
                                const std::vector<BruteChild<Model>>& merged, double tol,
                                double min_findable = 1e-5) {
  const double log_norm = log_normalizer(merged);
  ASSERT_GT(min_log_weight(merged), std::log(min_findable))
      << "the test problem must keep every hypothesis findable";
  EXPECT_NEAR(stats.log_normalizer, log_norm, tol);
  ASSERT_EQ(post.hypotheses.size(), merged.size());
  double total = 0.0;
  for (const auto& h : post.hypotheses) total += std::exp(h.log_weight);
  EXPECT_NEAR(total, 1.0, 1e-12);
  for (const auto& c : merged) {
    int found = 0;
    for (const auto& h : post.hypotheses) {
      if (h.tracks.size() != c.landmarks.size()) continue;
      bool same = true;
      for (auto t : h.tracks) {
        const auto it = c.landmarks.find(post.tracks[t].label.key());
        if (it == c.landmarks.end() || (it->second.mean - post.tracks[t].mean).norm() > tol) same = false;
      }
      if (!same) continue;
      ++found;
      EXPECT_NEAR(h.log_weight, c.log_w - log_norm, tol);
      for (auto t : h.tracks) {
        const auto& tr = post.tracks[t];
        const auto& lm = c.landmarks.at(tr.label.key());
        EXPECT_LT((lm.cov - tr.cov).norm(), tol)
            << "label (" << tr.label.birth_step << ", " << tr.label.index << ")";
        if constexpr (AppearanceOf<Model>::kEnabled) {
          EXPECT_TRUE(lm.appearance == tr.appearance);
        }
      }
    }
    EXPECT_EQ(found, 1);
  }
}

}  // namespace glmbslam::backend::enumeration
