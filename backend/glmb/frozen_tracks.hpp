#pragma once
// Freezing and thawing of far-away tracks (see glmb_map.hpp). Exact, not an approximation: a track that is in
// every hypothesis and out of view is copied unchanged into every child by the δ-GLMB update (p_D = 0,
// p_S = 1), which is what "frozen" means; it is thawed (returned to the table and to every hypothesis) before
// it can come into view again.
//
// With R_q = model.query_radius() + fov_margin (beyond it no track is ever active) and m = freeze_margin:
//   thaw   every frozen track within R_q + m of the sensor position, at the end of each update;
//   freeze the tracks that are in every hypothesis and farther than R_q + 2m (hysteresis), when there are at
//          least freeze_min_tracks of them (so blocks stay large and few).
// Exactness needs m ≥ the sensor's motion in one step plus the proposal's search margin (3σ of the predicted
// position), so that a frozen track is never within R_q of a pose the next step evaluates.
#include <algorithm>
#include <memory>
#include <vector>

#include "backend/glmb/glmb_config.hpp"
#include "backend/glmb/glmb_map.hpp"

namespace glmbslam::backend {

/// Squared distance from p to the axis-aligned box [lo, hi].
template <class V>
double squared_distance_to_box(const V& p, const V& lo, const V& hi) {
  return (p.cwiseMax(lo).cwiseMin(hi) - p).squaredNorm();
}

/// Sets the block's bounding box from its tracks (which must not be empty).
template <class Meas>
void set_bounds(FrozenBlock<Meas>& block) {
  block.lo = block.hi = Meas::landmark_position(block.tracks.front().mean);
  for (const auto& t : block.tracks) {
    block.lo = block.lo.cwiseMin(Meas::landmark_position(t.mean));
    block.hi = block.hi.cwiseMax(Meas::landmark_position(t.mean));
  }
}

/// Thaws the frozen tracks near `position` and freezes the far common ones, in place.
template <class Meas, class Position>
void freeze_and_thaw(const Meas& model, const GlmbConfig& config, const Position& position,
                     GlmbMap<Meas>& map, std::vector<int>& scratch) {
  if (config.freeze_margin <= 0.0) return;
  const double r_thaw = model.query_radius() + config.fov_margin + config.freeze_margin;
  const double r_freeze = r_thaw + config.freeze_margin;
  const double r_thaw2 = r_thaw * r_thaw, r_freeze2 = r_freeze * r_freeze;

  // thaw: blocks whose box reaches within r_thaw; their near tracks go back to the table (ids appended at the
  // end, so every hypothesis's id list stays sorted by appending them)
  if (map.frozen) {
    auto near = [&](const Track<Meas>& t) {
      return (Meas::landmark_position(t.mean) - position).squaredNorm() <= r_thaw2;
    };
    auto reaches = [&](const FrozenBlock<Meas>& b) {
      return squared_distance_to_box(position, b.lo, b.hi) <= r_thaw2 &&
             std::any_of(b.tracks.begin(), b.tracks.end(), near);
    };
    if (std::any_of(map.frozen->begin(), map.frozen->end(), [&](const auto& b) { return reaches(*b); })) {
      auto blocks = std::make_shared<FrozenBlockList<Meas>>();
      const std::uint32_t first = static_cast<std::uint32_t>(map.tracks.size());
      std::size_t remaining = 0;
      for (const auto& b : *map.frozen) {
        if (!reaches(*b)) {
          blocks->push_back(b);
          remaining += b->tracks.size();
          continue;
        }
        auto rest = std::make_shared<FrozenBlock<Meas>>();
        for (const auto& t : b->tracks) {
          if (near(t))
            map.tracks.push_back(t);
          else
            rest->tracks.push_back(t);
        }
        if (rest->tracks.empty()) continue;
        set_bounds(*rest);
        remaining += rest->tracks.size();
        blocks->push_back(std::move(rest));
      }
      const auto last = static_cast<std::uint32_t>(map.tracks.size());
      for (auto& h : map.hypotheses)
        for (std::uint32_t id = first; id < last; ++id) h.tracks.push_back(id);
      map.frozen_count = remaining;
      map.frozen =
          blocks->empty() ? nullptr : std::shared_ptr<const FrozenBlockList<Meas>>(std::move(blocks));
    }
  }

  // freeze: tracks in every hypothesis and farther than r_freeze
  const std::size_t n = map.tracks.size();
  std::vector<int>& count = scratch;
  count.assign(n, 0);
  for (const auto& h : map.hypotheses)
    for (std::uint32_t t : h.tracks) ++count[t];
  const int all = static_cast<int>(map.hypotheses.size());
  int candidates = 0;
  for (std::size_t t = 0; t < n; ++t) {
    if (count[t] == all &&
        (Meas::landmark_position(map.tracks[t].mean) - position).squaredNorm() > r_freeze2) {
      count[t] = -1;
      ++candidates;
    }
  }
  if (candidates < std::max(1, config.freeze_min_tracks)) return;
  auto block = std::make_shared<FrozenBlock<Meas>>();
  block->tracks.reserve(static_cast<std::size_t>(candidates));
  int next = 0;
  for (std::size_t t = 0; t < n; ++t) {  // count[] becomes the new index of a live track, −1 if frozen
    if (count[t] == -1) {
      block->tracks.push_back(map.tracks[t]);
    } else {
      map.tracks[static_cast<std::size_t>(next)] = map.tracks[t];
      count[t] = next++;
    }
  }
  map.tracks.resize(static_cast<std::size_t>(next));
  for (auto& h : map.hypotheses) {
    std::size_t w = 0;
    for (std::uint32_t t : h.tracks)
      if (count[t] >= 0) h.tracks[w++] = static_cast<std::uint32_t>(count[t]);
    h.tracks.resize(w);
  }
  set_bounds(*block);
  auto blocks = std::make_shared<FrozenBlockList<Meas>>();
  if (map.frozen) *blocks = *map.frozen;
  blocks->push_back(std::move(block));
  map.frozen_count += static_cast<std::size_t>(candidates);
  map.frozen = std::move(blocks);
}

}  // namespace glmbslam::backend
