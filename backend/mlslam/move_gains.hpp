#pragma once
// An upper bound on the change of the scan likelihood (paper 004 Eq. 7) when one landmark a is added to the
// map; the births of rfs_ml_slam.hpp skip the candidates whose bound summed over the scans is ≤ 0 (their
// Δl cannot be positive) before evaluating those scans again.
//
// Every association hypothesis θ of M extends to the hypotheses of M ∪ {a} where a is missed (factor
// 1 − p_D(a)) or detects one of the measurements θ leaves to clutter (factor p_D(a) g(z_n|x,a)/κ(z_n)), so
//   p(Z | x, M ∪ {a}) / p(Z | x, M) = 1 − p_D(a) + p_D(a) Σ_n P(z_n clutter | M) g(z_n|x,a)/κ(z_n)
//                                   ≤ 1 − p_D(a) + p_D(a) Σ_n g(z_n|x,a)/κ(z_n),
// the sums over the measurements within the gate of a. (The equality with the E-step's clutter
// responsibilities 1 − Σ_m β_mn is no safe filter: the ranked assignments truncate the small P(z_n clutter)
// of well-explained measurements to 0, which a landmark closer to z_n than its current one needs.)
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace glmbslam::backend {

/// The measurement density g(z | x, m) = N(z; ẑ, R) with R factorised once, and the gate of
/// evaluate_scan: a pair passes when (z − ẑ)ᵀ R⁻¹ (z − ẑ) ≤ gate, which needs |z_0 − ẑ_0| ≤ √(gate R_00).
template <class Model>
class GatedDensity {
 public:
  GatedDensity(const Model& model, double gate) : gate_(gate), llt_(model.noise()) {
    const auto& R = model.noise();
    double log_det = 0.0;
    for (Eigen::Index i = 0; i < R.rows(); ++i) log_det += std::log(llt_.matrixLLT()(i, i));
    log_norm_ = -0.5 * (static_cast<double>(R.rows()) * std::log(2.0 * M_PI) + 2.0 * log_det);
    window_ = std::sqrt(gate * R(0, 0)) * (1.0 + 1e-9) + 1e-12;
  }
  /// log g(z | ẑ), or −∞ beyond the gate.
  double log_density(const Model& model, const typename Model::Measurement& z,
                     const typename Model::Measurement& zhat) const {
    constexpr double kOut = -std::numeric_limits<double>::infinity();
    if (std::abs(z(0) - zhat(0)) > window_) return kOut;
    const double d2 = llt_.matrixL().solve(model.residual(z, zhat)).squaredNorm();
    return d2 <= gate_ ? log_norm_ - 0.5 * d2 : kOut;
  }

 private:
  using Covariance = typename std::decay_t<decltype(std::declval<Model>().noise())>::PlainObject;
  double gate_;
  Eigen::LLT<Covariance> llt_;
  double log_norm_ = 0.0, window_ = 0.0;
};

/// log of the upper bound above on p(Z | x, M ∪ {a}) / p(Z | x, M).
template <class Model, class Detection, class MeasurementList>
double log_birth_ratio_bound(const Model& model, const Detection& p_D, const GatedDensity<Model>& g,
                             const typename Model::Pose& x, const typename Model::Landmark& a,
                             const MeasurementList& Z) {
  const auto zhat = model.predict(x, a);
  const double p = p_D(model, x, a, zhat);
  if (p <= 0.0) return 0.0;
  double explained = 0.0;  // Σ_n g/κ
  for (const auto& z : Z) {
    const double lg = g.log_density(model, z, zhat);
    if (lg != -std::numeric_limits<double>::infinity())
      explained += std::exp(lg - model.log_clutter_intensity(z));
  }
  return std::log1p(p * (explained - 1.0));
}

}  // namespace glmbslam::backend
