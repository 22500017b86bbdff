#pragma once
// A δ-GLMB landmark map (paper 000 Eq. 24/28) truncated to a few hypotheses.
//
// The map owns a track table and a list of hypotheses. A track is one labelled landmark density: label
// ℓ = (birth step, index) and a Gaussian N(mean, cov). (With EKF updates and single-Gaussian births each
// label's density inside one hypothesis stays a single Gaussian, so the GM of Eq. 28 has one component per
// track; the same label can appear in several tracks with different densities, one per association history.)
// A hypothesis holds its normalised log weight and the sorted indices of its tracks. Every track is
// referenced by at least one hypothesis (the update compacts the table), so memory stays bounded. Maps are
// immutable once built and shared between particles through shared_ptr<const GlmbMap>.
//
// Frozen tracks (frozen_tracks.hpp): tracks far from the sensor that belong to EVERY hypothesis leave the
// table and the hypotheses for immutable blocks shared between maps (and particles, and time steps); every
// hypothesis implicitly contains all of them. Out of view they would only be copied through unchanged, so
// the update's cost depends on the live part of the map near the sensor, not on the whole map.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "backend/glmb/appearance.hpp"
#include "core/log_math.hpp"

namespace glmbslam::backend {

/// Track label ℓ = (k, i): born at time step k from measurement i of the previous scan.
struct Label {
  std::int32_t birth_step = 0;
  std::int32_t index = 0;
  bool operator==(const Label& o) const { return birth_step == o.birth_step && index == o.index; }
  bool operator!=(const Label& o) const { return !(*this == o); }
  bool operator<(const Label& o) const {
    return birth_step != o.birth_step ? birth_step < o.birth_step : index < o.index;
  }
  std::uint64_t key() const {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(birth_step)) << 32) |
           static_cast<std::uint32_t>(index);
  }
};

template <class Meas>
struct Track {
  Label label;
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  typename AppearanceOf<Meas>::Type appearance{};  ///< e.g. the last ORB descriptor matched (appearance.hpp)
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

struct Hypothesis {
  double log_weight = 0.0;            ///< normalised: Σ_h exp(log_weight) = 1
  std::vector<std::uint32_t> tracks;  ///< sorted indices into GlmbMap::tracks
};

/// A Bernoulli birth candidate for the next update (adaptive birth from the last scan, Eq. 27).
template <class Meas>
struct BirthCandidate {
  Label label;
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  double log_existence = kLogZero;  ///< log r_B
  typename AppearanceOf<Meas>::Type appearance{};
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// An immutable block of frozen tracks with the bounding box of their landmark positions.
template <class Meas>
struct FrozenBlock {
  using Position = std::decay_t<decltype(Meas::landmark_position(std::declval<typename Meas::Landmark>()))>;
  std::vector<Track<Meas>, Eigen::aligned_allocator<Track<Meas>>> tracks;
  Position lo, hi;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
template <class Meas>
using FrozenBlockList = std::vector<std::shared_ptr<const FrozenBlock<Meas>>>;

template <class Meas>
struct GlmbMap {
  using TrackType = Track<Meas>;
  std::vector<TrackType, Eigen::aligned_allocator<TrackType>> tracks;
  std::vector<Hypothesis> hypotheses;  ///< sorted by decreasing weight
  std::vector<BirthCandidate<Meas>, Eigen::aligned_allocator<BirthCandidate<Meas>>> births;
  std::shared_ptr<const FrozenBlockList<Meas>> frozen;  ///< in every hypothesis; null = none
  std::size_t frozen_count = 0;                         ///< tracks in the frozen blocks

  /// Live plus frozen tracks.
  std::size_t total_tracks() const { return tracks.size() + frozen_count; }
  /// Calls f(track) for every frozen track.
  template <class F>
  void for_each_frozen(F&& f) const {
    if (!frozen) return;
    for (const auto& b : *frozen)
      for (const auto& t : b->tracks) f(t);
  }

  /// The empty map: one hypothesis (the empty label set) with weight 1.
  static GlmbMap empty() {
    GlmbMap m;
    m.hypotheses.push_back(Hypothesis{0.0, {}});
    return m;
  }

  /// Marks the tracks that may be in the sensor's view at `x` (p_D > 0 or p_S < 1): active[t] = true.
  /// Tracks farther than query_radius + margin from the sensor are rejected with one distance test.
  /// With `pd`, also stores p_D(tracks[t].mean | x) in (*pd)[t] for every active track t.
  template <class Pose>
  void find_active(const Meas& model, const Pose& x, double margin, std::vector<char>& active,
                   std::vector<double>* pd = nullptr) const {
    active.assign(tracks.size(), 0);
    if (pd != nullptr) pd->resize(tracks.size());
    const auto p = Meas::position(x);
    const double r = model.query_radius() + margin;
    const double r2 = r * r;
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      if ((Meas::landmark_position(tracks[t].mean) - p).squaredNorm() > r2) continue;
      const auto& m = tracks[t].mean;
      const double p_d = model.detection_probability(x, m);
      active[t] = p_d > 0.0 || model.survival_probability(x, m) < 1.0;
      if (pd != nullptr) (*pd)[t] = p_d;
    }
  }
};

template <class Meas>
struct LandmarkEstimate {
  Label label;
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  double existence = 0.0;  ///< Σ of the weights of the hypotheses containing the label
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// ρ(n) = Σ_{h: |I_h| = n} ω_h for n = 0..max, counting the frozen tracks (in every hypothesis).
template <class Meas>
std::vector<double> cardinality_distribution(const GlmbMap<Meas>& map) {
  std::vector<double> rho;
  for (const auto& h : map.hypotheses) {
    const std::size_t n = h.tracks.size() + map.frozen_count;
    if (rho.size() <= n) rho.resize(n + 1, 0.0);
    rho[n] += std::exp(h.log_weight);
  }
  return rho;
}

/// Map estimate (Sec. 3.1): MAP cardinality n̂, then the best hypothesis with n̂ labels; each of its
/// landmarks with its existence probability.
template <class Meas>
std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>> estimate_map(
    const GlmbMap<Meas>& map) {
  std::vector<LandmarkEstimate<Meas>, Eigen::aligned_allocator<LandmarkEstimate<Meas>>> out;
  if (map.hypotheses.empty()) return out;
  const std::vector<double> rho = cardinality_distribution(map);
  const std::size_t n_hat = static_cast<std::size_t>(std::max_element(rho.begin(), rho.end()) - rho.begin());
  const Hypothesis* best = nullptr;
  for (const auto& h : map.hypotheses) {
    if (h.tracks.size() + map.frozen_count == n_hat && (best == nullptr || h.log_weight > best->log_weight))
      best = &h;
  }
  std::unordered_map<std::uint64_t, double> existence;
  for (const auto& h : map.hypotheses) {
    const double w = std::exp(h.log_weight);
    for (std::uint32_t t : h.tracks) existence[map.tracks[t].label.key()] += w;
  }
  out.reserve(best->tracks.size() + map.frozen_count);
  map.for_each_frozen([&](const Track<Meas>& tr) {
    LandmarkEstimate<Meas> e;
    e.label = tr.label;
    e.mean = tr.mean;
    e.cov = tr.cov;
    e.existence = 1.0;  // in every hypothesis
    out.push_back(e);
  });
  for (std::uint32_t t : best->tracks) {
    const auto& tr = map.tracks[t];
    LandmarkEstimate<Meas> e;
    e.label = tr.label;
    e.mean = tr.mean;
    e.cov = tr.cov;
    e.existence = std::min(1.0, existence[tr.label.key()]);
    out.push_back(e);
  }
  return out;
}

}  // namespace glmbslam::backend
