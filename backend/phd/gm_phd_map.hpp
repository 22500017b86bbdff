#pragma once
// Gaussian-mixture PHD landmark map of one particle and its update at a known pose (RB-PHD-SLAM, paper 002
// Eq. 12 and Sec. IV-A; digest 1.2–1.4, 2.2). Templated on a MeasurementModel (backend/models).
//
// update(prior, x, Z):
//  1. Active components: those within query_radius + fov_margin of the sensor with p_D(mean) > 0; the others
//     (passive) are copied unchanged (p_D = 0: the update leaves them as they are).
//  2. Per active component a: ẑ_a, H_a = ∂h/∂m, S_a = H_a P_a H_aᵀ + R, K_a, P_a⁺ = (I − K_a H_a) P_a (EKF).
//  3. Missed: (1 − p_D,a) w_a, same moments. Detected by z_j (inside the χ² gate νᵀS⁻¹ν ≤ gate_threshold):
//       w = p_D,a w_a q_a(z_j) / (κ(z_j) + Σ_b p_D,b w_b q_b(z_j)),  q_a(z) = N(z; ẑ_a, S_a),  mean μ_a + K_a
//       ν.
//  4. The particle log-likelihood log g(Z_k | Z_{1:k−1}, X_{0:k}) by the configured form
//  (PhdConfig::likelihood):
//       empty_map:      Σ_z log κ(z) + N̂_k − N̂_{k|k−1} − λ_c                                (002 Eq. 15)
//       single_feature: the same identity at M = {m̄}, m̄ = mean of the strongest updated component:
//                       + log[(1 − p_D(m̄)) + p_D(m̄) Σ_z g(z|m̄)/κ(z)] + log v_{k|k−1}(m̄) − log v_k(m̄)
//                       (v evaluated over the active components; passive ones are far from m̄)
//       poisson:        −λ_c − Σ_a p_D,a w_a + Σ_z log(κ(z) + Σ_a p_D,a w_a q_a(z))          (003 Eq. 46 +
//       the
//                       expected-detections term the digest recommends)
//     (N̂ differences only involve active components: the passive ones are unchanged.)
//  5. Pruning (weight < prune_threshold) and merging (Mahalanobis² ≤ merge_threshold around the strongest
//     component, Vo & Ma 2006) of the updated active components; cap at max_components (highest weights).
//  6. Births for the next step: one component per measurement that gated with no active component (or per
//     measurement, birth_from_all) through the inverse measurement model at x, weight birth_weight (003).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include "backend/phd/phd_config.hpp"
#include "core/error.hpp"
#include "core/log_math.hpp"

namespace glmbslam::backend {

template <class Meas>
struct GmPhdComponent {
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  double weight = 0.0;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

template <class Meas>
struct GmPhdMap {
  using Component = GmPhdComponent<Meas>;
  using Components = std::vector<Component, Eigen::aligned_allocator<Component>>;
  Components components;

  /// N̂ = ∫v: the expected number of landmarks.
  double expected_count() const {
    double s = 0.0;
    for (const auto& c : components) s += c.weight;
    return s;
  }
};

struct GmPhdUpdateStats {
  double log_likelihood = 0.0;  ///< log g(Z_k | Z_{1:k−1}, X_{0:k}) by the configured form
  int components = 0;           ///< components after the update (including births)
  int active = 0;               ///< active components before the update
  int births = 0;               ///< birth components added
};

template <class Meas>
class GmPhdUpdater {
 public:
  using Map = GmPhdMap<Meas>;
  using Component = GmPhdComponent<Meas>;
  using Pose = typename Meas::Pose;
  using Measurement = typename Meas::Measurement;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using Landmark = typename Meas::Landmark;
  using LandmarkCovariance = typename Meas::LandmarkCovariance;
  using MeasurementCovariance = typename Meas::MeasurementCovariance;
  using Gain = Eigen::Matrix<double, Meas::kLandmarkDim, Meas::kMeasDim>;
  static constexpr int kMeasDim = Meas::kMeasDim;

  enum class Likelihood { kEmptyMap, kSingleFeature, kPoisson };

  GmPhdUpdater(const Meas& model, const PhdConfig& config) : model_(model), config_(config) {
    validate_phd_config(config);
    likelihood_ = config.likelihood == "poisson"          ? Likelihood::kPoisson
                  : config.likelihood == "single_feature" ? Likelihood::kSingleFeature
                                                          : Likelihood::kEmptyMap;
  }

  /// Throws InputError naming the step and measurement if a measurement is not finite.
  void validate(const MeasurementSet& Z, int step) const {
    for (std::size_t j = 0; j < Z.size(); ++j) {
      if (!model_.is_finite(Z[j])) {
        throw InputError("measurement set", "time step " + std::to_string(step) + ": measurement " +
                                                std::to_string(j) + " is not finite");
      }
    }
  }

  GmPhdUpdateStats update(const Map& prior, const Pose& x, const MeasurementSet& Z, Map& posterior) const {
    Workspace& ws = workspace();
    posterior.components.clear();
    posterior.components.reserve(prior.components.size() + 4 * Z.size() + 8);
    GmPhdUpdateStats stats;

    // 1. active / passive split
    ws.active.clear();
    const auto p = Meas::position(x);
    const double r = model_.query_radius() + config_.fov_margin;
    for (std::size_t c = 0; c < prior.components.size(); ++c) {
      const Component& comp = prior.components[c];
      const bool near = (Meas::landmark_position(comp.mean) - p).squaredNorm() <= r * r;
      if (near && model_.detection_probability(x, comp.mean) > 0.0) {
        ws.active.push_back(static_cast<int>(c));
      } else {
        posterior.components.push_back(comp);
      }
    }
    const int A = static_cast<int>(ws.active.size());
    const int J = static_cast<int>(Z.size());
    stats.active = A;

    // 2. EKF terms per active component
    ws.zhat.resize(A);
    ws.S_inv.resize(A);
    ws.gain.resize(A);
    ws.cov_post.resize(A);
    ws.log_norm.resize(A);
    ws.pd.resize(A);
    double pred_weight = 0.0, expected_detections = 0.0;
    for (int a = 0; a < A; ++a) {
      const Component& comp = prior.components[static_cast<std::size_t>(ws.active[a])];
      typename Meas::LandmarkJacobian H;
      ws.zhat[a] = model_.linearize(x, comp.mean, nullptr, &H);
      MeasurementCovariance S = H * comp.cov * H.transpose() + model_.noise();
      S = (0.5 * (S + S.transpose())).eval();
      const Eigen::LLT<MeasurementCovariance> llt(S);
      ws.S_inv[a] = llt.solve(MeasurementCovariance::Identity());
      ws.gain[a] = comp.cov * H.transpose() * ws.S_inv[a];
      LandmarkCovariance P = comp.cov - ws.gain[a] * H * comp.cov;
      ws.cov_post[a] = (0.5 * (P + P.transpose())).eval();
      double log_det = 0.0;
      for (int i = 0; i < kMeasDim; ++i) log_det += 2.0 * std::log(llt.matrixLLT()(i, i));
      ws.log_norm[a] = -0.5 * (kMeasDim * std::log(2.0 * M_PI) + log_det);
      ws.pd[a] = model_.detection_probability(x, comp.mean);
      pred_weight += comp.weight;
      expected_detections += ws.pd[a] * comp.weight;
    }

    // 3. missed and detected components (into the scratch list, pruned/merged below)
    ws.updated.clear();
    for (int a = 0; a < A; ++a) {
      const Component& comp = prior.components[static_cast<std::size_t>(ws.active[a])];
      ws.updated.push_back(Component{comp.mean, comp.cov, (1.0 - ws.pd[a]) * comp.weight});
    }
    ws.explained.assign(static_cast<std::size_t>(J), 0);
    ws.log_den.resize(J);
    double sum_log_kappa = 0.0;
    for (int j = 0; j < J; ++j) {
      const double log_kappa = model_.log_clutter_intensity(Z[static_cast<std::size_t>(j)]);
      sum_log_kappa += log_kappa;
      const std::size_t first = ws.updated.size();
      ws.log_num.clear();
      for (int a = 0; a < A; ++a) {
        const Component& comp = prior.components[static_cast<std::size_t>(ws.active[a])];
        const Measurement nu = model_.residual(Z[static_cast<std::size_t>(j)], ws.zhat[a]);
        const double d2 = nu.dot(ws.S_inv[a] * nu);
        if (!(d2 <= config_.gate_threshold)) continue;
        ws.explained[static_cast<std::size_t>(j)] = 1;
        const double log_num = std::log(ws.pd[a] * comp.weight) + ws.log_norm[a] - 0.5 * d2;
        ws.log_num.push_back(log_num);
        ws.updated.push_back(Component{comp.mean + ws.gain[a] * nu, ws.cov_post[a], 0.0});
      }
      double log_den = log_kappa;
      for (double l : ws.log_num) log_den = log_add(log_den, l);
      ws.log_den[j] = log_den;
      for (std::size_t t = 0; t < ws.log_num.size(); ++t) {
        ws.updated[first + t].weight = std::exp(ws.log_num[t] - log_den);
      }
    }
    double post_weight = 0.0;
    for (const auto& c : ws.updated) post_weight += c.weight;

    // 4. particle likelihood
    const double lambda = model_.clutter_rate();
    double log_g = sum_log_kappa + post_weight - pred_weight - lambda;
    if (likelihood_ == Likelihood::kPoisson) {
      log_g = -lambda - expected_detections;
      for (int j = 0; j < J; ++j) log_g += ws.log_den[j];
    } else if (likelihood_ == Likelihood::kSingleFeature && !ws.updated.empty()) {
      std::size_t best = 0;
      for (std::size_t t = 1; t < ws.updated.size(); ++t) {
        if (ws.updated[t].weight > ws.updated[best].weight) best = t;
      }
      const Landmark m_bar = ws.updated[best].mean;
      double v_pred = 0.0, v_post = 0.0;
      for (int a = 0; a < A; ++a) {
        const Component& comp = prior.components[static_cast<std::size_t>(ws.active[a])];
        v_pred += comp.weight * gaussian_density(m_bar, comp.mean, comp.cov);
      }
      for (const auto& c : ws.updated) v_post += c.weight * gaussian_density(m_bar, c.mean, c.cov);
      const double pd_bar = model_.detection_probability(x, m_bar);
      const Measurement z_bar = model_.predict(x, m_bar);
      const Eigen::LLT<MeasurementCovariance> r_llt(model_.noise());
      double log_det_r = 0.0;
      for (int i = 0; i < kMeasDim; ++i) log_det_r += 2.0 * std::log(r_llt.matrixLLT()(i, i));
      double ratio_sum = 0.0;  // Σ_z g(z|m̄)/κ(z)
      for (int j = 0; j < J; ++j) {
        const Measurement nu = model_.residual(Z[static_cast<std::size_t>(j)], z_bar);
        const double log_gz =
            -0.5 * (kMeasDim * std::log(2.0 * M_PI) + log_det_r + r_llt.matrixL().solve(nu).squaredNorm());
        ratio_sum += std::exp(log_gz - model_.log_clutter_intensity(Z[static_cast<std::size_t>(j)]));
      }
      const double bracket = (1.0 - pd_bar) + pd_bar * ratio_sum;
      if (v_pred > 0.0 && v_post > 0.0 && bracket > 0.0) {
        log_g += std::log(bracket) + std::log(v_pred) - std::log(v_post);
      }
    }
    stats.log_likelihood = log_g;

    // 5. prune, merge, cap
    prune_and_merge(ws.updated, ws);
    posterior.components.insert(posterior.components.end(), ws.updated.begin(), ws.updated.end());

    // 6. births for the next step
    for (int j = 0; j < J; ++j) {
      if (!config_.birth_from_all && ws.explained[static_cast<std::size_t>(j)] != 0) continue;
      Component b;
      model_.initialize(x, Z[static_cast<std::size_t>(j)], &b.mean, &b.cov);
      b.weight = config_.birth_weight;
      posterior.components.push_back(b);
      ++stats.births;
    }
    stats.components = static_cast<int>(posterior.components.size());
    return stats;
  }

  /// Landmarks of the map estimate: components with weight above existence_threshold (002).
  std::vector<Component, Eigen::aligned_allocator<Component>> estimate(const Map& map) const {
    std::vector<Component, Eigen::aligned_allocator<Component>> out;
    for (const auto& c : map.components) {
      if (c.weight > config_.existence_threshold) out.push_back(c);
    }
    return out;
  }

  const PhdConfig& config() const { return config_; }
  const Meas& model() const { return model_; }

 private:
  using Components = typename Map::Components;

  struct Workspace {
    std::vector<int> active;
    std::vector<Measurement, Eigen::aligned_allocator<Measurement>> zhat;
    std::vector<MeasurementCovariance, Eigen::aligned_allocator<MeasurementCovariance>> S_inv;
    std::vector<Gain, Eigen::aligned_allocator<Gain>> gain;
    std::vector<LandmarkCovariance, Eigen::aligned_allocator<LandmarkCovariance>> cov_post, cov_inv;
    std::vector<double> log_norm, pd, log_den, log_num;
    std::vector<char> explained, used;
    std::vector<int> order;
    Components updated, merged;
  };
  static Workspace& workspace() {
    thread_local Workspace ws;
    return ws;
  }

  static double gaussian_density(const Landmark& m, const Landmark& mean, const LandmarkCovariance& cov) {
    const Eigen::LLT<LandmarkCovariance> llt(cov);
    if (llt.info() != Eigen::Success) return 0.0;
    double log_det = 0.0;
    for (int i = 0; i < Meas::kLandmarkDim; ++i) log_det += 2.0 * std::log(llt.matrixLLT()(i, i));
    const double d2 = llt.matrixL().solve(m - mean).squaredNorm();
    return std::exp(-0.5 * (Meas::kLandmarkDim * std::log(2.0 * M_PI) + log_det + d2));
  }

  /// Vo & Ma (2006) pruning and merging, then the cap (highest weights kept).
  void prune_and_merge(Components& comps, Workspace& ws) const {
    // prune
    std::size_t kept = 0;
    for (std::size_t t = 0; t < comps.size(); ++t) {
      if (comps[t].weight >= config_.prune_threshold) comps[kept++] = comps[t];
    }
    comps.resize(kept);
    if (comps.empty()) return;
    // merge: repeatedly take the strongest unused component and absorb those within U of it
    const std::size_t n = comps.size();
    ws.order.resize(n);
    std::iota(ws.order.begin(), ws.order.end(), 0);
    std::sort(ws.order.begin(), ws.order.end(), [&](int a, int b) {
      return comps[static_cast<std::size_t>(a)].weight > comps[static_cast<std::size_t>(b)].weight;
    });
    ws.cov_inv.resize(n);
    for (std::size_t t = 0; t < n; ++t) ws.cov_inv[t] = comps[t].cov.inverse();
    ws.used.assign(n, 0);
    ws.merged.clear();
    for (int oi : ws.order) {
      const auto i = static_cast<std::size_t>(oi);
      if (ws.used[i] != 0) continue;
      double w = 0.0;
      Landmark mean = Landmark::Zero();
      for (std::size_t t = 0; t < n; ++t) {
        if (ws.used[t] != 0) continue;
        const Landmark d = comps[t].mean - comps[i].mean;
        if (d.dot(ws.cov_inv[t] * d) <= config_.merge_threshold) {
          ws.used[t] = 2;  // member of the current cluster
          w += comps[t].weight;
          mean += comps[t].weight * comps[t].mean;
        }
      }
      mean /= w;
      LandmarkCovariance cov = LandmarkCovariance::Zero();
      for (std::size_t t = 0; t < n; ++t) {
        if (ws.used[t] != 2) continue;
        const Landmark d = comps[t].mean - mean;
        cov += comps[t].weight * (comps[t].cov + d * d.transpose());
        ws.used[t] = 1;
      }
      cov /= w;
      ws.merged.push_back(Component{mean, (0.5 * (cov + cov.transpose())).eval(), w});
    }
    comps.swap(ws.merged);
    if (static_cast<int>(comps.size()) > config_.max_components) {
      std::nth_element(comps.begin(), comps.begin() + config_.max_components, comps.end(),
                       [](const Component& a, const Component& b) { return a.weight > b.weight; });
      comps.resize(static_cast<std::size_t>(config_.max_components));
    }
  }

  Meas model_;
  PhdConfig config_;
  Likelihood likelihood_ = Likelihood::kEmptyMap;
};

}  // namespace glmbslam::backend
