#pragma once
// A labelled multi-Bernoulli (LMB) landmark map: one Bernoulli per label ℓ with existence r_ℓ and a Gaussian
// mixture density p_ℓ (LMB-SLAM: Deusch, Reuter & Dietmayer 2015, cited by paper 000). Maps are immutable
// once built and shared between particles through shared_ptr<const LmbMap>.
//
// The LMB approximation of a δ-GLMB density {(I_h, ω_h, p^(h))} (Reuter et al. 2014, Eq. 21–22):
//   r_ℓ = Σ_{h: ℓ ∈ I_h} ω_h,    p_ℓ(m) = (1 / r_ℓ) Σ_{h: ℓ ∈ I_h} ω_h p_ℓ^(h)(m)
// — it keeps each label's existence probability and spatial density (the first moment of the labelled
// RFS); what it drops is the correlation between labels. lmb_from_glmb() computes it for a GlmbMap (one
// Gaussian per track); LmbUpdater (lmb_update.hpp) computes it directly from the sampled association maps.
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "backend/glmb/glmb_map.hpp"
#include "core/gaussian.hpp"

namespace glmbslam::backend {

template <class Meas>
struct LmbComponent {
  double weight = 0.0;  ///< within its label, normalised: Σ = 1
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

template <class Meas>
struct LmbTrack {
  Label label;
  double existence = 0.0;  ///< r_ℓ
  int first = 0;           ///< its components: LmbMap::components[first, first + count)
  int count = 0;
  typename AppearanceOf<Meas>::Type appearance{};
};

template <class Meas>
struct LmbMap {
  using Component = LmbComponent<Meas>;
  std::vector<LmbTrack<Meas>> tracks;
  std::vector<Component, Eigen::aligned_allocator<Component>> components;
  std::vector<BirthCandidate<Meas>, Eigen::aligned_allocator<BirthCandidate<Meas>>> births;

  /// The highest-weight component of track t (the point estimate and where p_D, p_S are evaluated).
  const Component& dominant(std::size_t t) const {
    const LmbTrack<Meas>& tr = tracks[t];
    int best = tr.first;
    for (int c = tr.first + 1; c < tr.first + tr.count; ++c)
      if (components[c].weight > components[best].weight) best = c;
    return components[static_cast<std::size_t>(best)];
  }
  /// Appends a track with the given components (weights normalised here).
  template <class ComponentRange>
  void add_track(const Label& label, double existence, const ComponentRange& comps,
                 const typename AppearanceOf<Meas>::Type& appearance = {}) {
    LmbTrack<Meas> tr;
    tr.label = label;
    tr.existence = existence;
    tr.first = static_cast<int>(components.size());
    tr.count = static_cast<int>(comps.size());
    tr.appearance = appearance;
    double total = 0.0;
    for (const auto& c : comps) total += c.weight;
    for (const auto& c : comps) {
      components.push_back(c);
      components.back().weight = c.weight / total;
    }
    tracks.push_back(tr);
  }
};

/// Moment matching of weighted Gaussians (weights need not be normalised): the single Gaussian with the
/// mixture's mean and covariance.
template <class Meas, class It>
LmbComponent<Meas> merge_components(It first, It last) {
  LmbComponent<Meas> out;
  double total = 0.0;
  out.mean.setZero();
  out.cov.setZero();
  for (It it = first; it != last; ++it) {
    total += it->weight;
    out.mean += it->weight * it->mean;
  }
  out.mean /= total;
  for (It it = first; it != last; ++it) {
    const typename Meas::Landmark d = it->mean - out.mean;
    out.cov += it->weight * (it->cov + d * d.transpose());
  }
  out.cov /= total;
  symmetrize(out.cov);
  out.weight = total;
  return out;
}

/// Reduces a label's components (any weights) in place: sorted by decreasing weight, relative weights below
/// `prune` dropped (the best kept), at most `max_components` (the tail merged into one by moment matching).
template <class Meas>
void reduce_components(std::vector<LmbComponent<Meas>, Eigen::aligned_allocator<LmbComponent<Meas>>>& comps,
                       double prune, int max_components) {
  std::stable_sort(comps.begin(), comps.end(),
                   [](const auto& a, const auto& b) { return a.weight > b.weight; });
  double total = 0.0;
  for (const auto& c : comps) total += c.weight;
  std::size_t keep = 1;
  while (keep < comps.size() && comps[keep].weight >= prune * total) ++keep;
  comps.resize(keep);
  const std::size_t cap = static_cast<std::size_t>(max_components);
  if (comps.size() > cap) {
    const LmbComponent<Meas> tail =
        merge_components<Meas>(comps.begin() + static_cast<std::ptrdiff_t>(cap - 1), comps.end());
    comps.resize(cap - 1);
    comps.push_back(tail);
  }
}

/// The LMB approximation of a δ-GLMB map (exact: one component per (label, hypothesis density), equal
/// densities of a label summed). Frozen tracks are in every hypothesis: existence 1. Births are copied.
template <class Meas>
LmbMap<Meas> lmb_from_glmb(const GlmbMap<Meas>& glmb) {
  using Comp = LmbComponent<Meas>;
  LmbMap<Meas> out;
  // per label, in order of first appearance: the tracks (densities) and the weight of each
  std::unordered_map<std::uint64_t, std::size_t> slot;
  std::vector<Label> labels;
  std::vector<std::vector<std::pair<std::uint32_t, double>>> mass;
  for (const auto& h : glmb.hypotheses) {
    const double w = std::exp(h.log_weight);
    for (const std::uint32_t t : h.tracks) {
      const Label& l = glmb.tracks[t].label;
      const auto [it, inserted] = slot.emplace(l.key(), labels.size());
      if (inserted) {
        labels.push_back(l);
        mass.emplace_back();
      }
      auto& m = mass[it->second];
      auto e = std::find_if(m.begin(), m.end(), [&](const auto& p) { return p.first == t; });
      if (e == m.end())
        m.emplace_back(t, w);
      else
        e->second += w;
    }
  }
  std::vector<Comp, Eigen::aligned_allocator<Comp>> comps;
  glmb.for_each_frozen([&](const Track<Meas>& tr) {
    comps.assign(1, Comp{1.0, tr.mean, tr.cov});
    out.add_track(tr.label, 1.0, comps, tr.appearance);
  });
  for (std::size_t i = 0; i < labels.size(); ++i) {
    comps.clear();
    double r = 0.0;
    for (const auto& [t, w] : mass[i]) {
      comps.push_back(Comp{w, glmb.tracks[t].mean, glmb.tracks[t].cov});
      r += w;
    }
    out.add_track(labels[i], std::min(1.0, r), comps, glmb.tracks[mass[i].front().first].appearance);
  }
  out.births.assign(glmb.births.begin(), glmb.births.end());
  return out;
}

/// Map estimate: the labels with existence above `threshold`, each at its highest-weight component.
template <class Meas>
std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>> estimate_lmb_map(
    const LmbMap<Meas>& map, double threshold) {
  std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>> out;
  for (std::size_t t = 0; t < map.tracks.size(); ++t) {
    if (!(map.tracks[t].existence > threshold)) continue;
    const LmbComponent<Meas>& c = map.dominant(t);
    LandmarkEstimate<Meas> e;
    e.label = map.tracks[t].label;
    e.mean = c.mean;
    e.cov = c.cov;
    e.existence = map.tracks[t].existence;
    out.push_back(e);
  }
  return out;
}

}  // namespace glmbslam::backend
