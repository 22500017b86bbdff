#pragma once
// Drawing from and evaluating a Gaussian mixture over poses, q(x) = Σ_c w_c N(x ⊖ μ_c; 0, Σ_c), as the
// proposals built from association hypotheses use it (optimal_proposal.hpp: paper 000 Eq. 30 when it keeps a
// mixture; mh_proposal.hpp: paper 003's multi-hypothesis importance density). A component is anything with
// `log_weight` (normalised), `mean` (a State) and `cov` (tangent covariance).
#include <cmath>
#include <cstddef>

#include "core/gaussian.hpp"
#include "core/log_math.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

/// c ~ Categorical(w): one uniform draw from `rng`.
template <class Components>
std::size_t draw_mixture_component(const Components& components, RandomStream& rng) {
  double u = rng.uniform();
  std::size_t c = 0;
  for (; c + 1 < components.size(); ++c) {
    u -= std::exp(components[c].log_weight);
    if (u < 0.0) break;
  }
  return c;
}

/// c ~ Categorical(w), then x ~ N(μ_c, Σ_c) on the manifold of Motion.
template <class Motion, class Components>
typename Motion::State draw_from_pose_mixture(const Components& components, RandomStream& rng) {
  const std::size_t c = draw_mixture_component(components, rng);
  return Motion::retract(components[c].mean,
                         rng.gaussian<Motion::kDim>(Motion::Tangent::Zero(), components[c].cov));
}

/// log q(x) = log Σ_c w_c N(x ⊖ μ_c; 0, Σ_c).
template <class Motion, class Components>
double log_pose_mixture_density(const Components& components, const typename Motion::State& x) {
  double s = kLogZero;
  for (const auto& c : components)
    s = log_add(s, c.log_weight + log_gaussian(Motion::local(x, c.mean), c.cov));
  return s;
}

}  // namespace glmbslam::backend
