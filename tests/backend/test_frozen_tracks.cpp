// Frozen tracks (backend/glmb/frozen_tracks.hpp): freezing far tracks that are in every hypothesis and
// thawing them before they come back into view must not change the δ-GLMB update. A sensor drives 120 m down
// a corridor of landmarks and back (every landmark leaves the view and is revisited); the update with
// freezing must give the same map estimate as the update without it at every step, while the live table
// stays small and the frozen tracks come back on the way home.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "backend/glmb/glmb_update.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {
namespace {

using Model = RangeBearingModel;
using Map = GlmbMap<Model>;
using Updater = GlmbUpdater<Model>;
using Z = Updater::MeasurementSet;

RangeBearingConfig corridor_sensor() {
  RangeBearingConfig c;
  c.sigma_range = 0.05;
  c.sigma_bearing = 0.5 * M_PI / 180.0;
  c.max_range = 8.0;
  c.half_fov = M_PI;  // 360°
  c.p_detect_inside = 0.9;
  c.p_survive_inside = 1.0;
  c.clutter_rate = 1.0;
  return c;
}

std::vector<Eigen::Vector2d> corridor_landmarks() {
  std::vector<Eigen::Vector2d> m;
  for (double x = 0.0; x <= 120.0; x += 4.0) {
    m.emplace_back(x, 3.0);
    m.emplace_back(x + 2.0, -3.0);
  }
  return m;
}

Z simulate(const Model& model, const Pose2& x, const std::vector<Eigen::Vector2d>& landmarks,
           RandomStream& rng) {
  const RangeBearingConfig c = corridor_sensor();
  Z z;
  for (const auto& m : landmarks) {
    if (model.detection_probability(x, m) <= 0.0 || rng.uniform() > c.p_detect_inside) continue;
    Eigen::Vector2d v = model.predict(x, m);
    v(0) += c.sigma_range * rng.normal();
    v(1) += c.sigma_bearing * rng.normal();
    z.push_back(v);
  }
  const int clutter = rng.poisson(c.clutter_rate);
  for (int i = 0; i < clutter; ++i) z.emplace_back(rng.uniform(0.1, c.max_range), rng.uniform(-M_PI, M_PI));
  return z;
}

std::map<std::uint64_t, Eigen::Vector2d> estimate_by_label(const Map& map) {
  std::map<std::uint64_t, Eigen::Vector2d> out;
  for (const auto& e : estimate_map(map)) out[e.label.key()] = e.mean;
  return out;
}

TEST(FrozenTracks, FreezingAndThawingLeaveTheUpdateUnchanged) {
  const Model model(corridor_sensor());
  GlmbConfig plain;
  plain.gibbs_samples = 200;
  plain.max_hypotheses = 30;
  GlmbConfig freezing = plain;
  freezing.freeze_margin = 3.0;  // > 1 m of motion per step; no proposal margin here (known poses)
  freezing.freeze_min_tracks = 4;
  const Updater updater_plain(model, plain), updater_freezing(model, freezing);
  const auto landmarks = corridor_landmarks();

  Map a = Map::empty(), b = Map::empty();
  std::size_t max_frozen = 0, max_live = 0, frozen_at_turn = 0;
  int thaws = 0;
  const int out_steps = 120;
  for (int k = 0; k <= 2 * out_steps; ++k) {
    const double s = k <= out_steps ? k : 2 * out_steps - k;  // out and back
    const Pose2 x(s, 0.0, k <= out_steps ? 0.0 : M_PI);
    RandomStream sim(7, static_cast<std::uint64_t>(k));
    const Z z = simulate(model, x, landmarks, sim);
    RandomStream rng_a(11, static_cast<std::uint64_t>(k)), rng_b(11, static_cast<std::uint64_t>(k));
    Map next_a, next_b;
    updater_plain.update(a, x, z, k, rng_a, next_a);
    updater_freezing.update(b, x, z, k, rng_b, next_b);
    if (next_b.frozen_count < b.frozen_count) ++thaws;
    a = std::move(next_a);
    b = std::move(next_b);
    max_frozen = std::max(max_frozen, b.frozen_count);
    max_live = std::max(max_live, b.tracks.size());
    if (k == out_steps) frozen_at_turn = b.frozen_count;

    const auto ea = estimate_by_label(a), eb = estimate_by_label(b);
    ASSERT_EQ(ea.size(), eb.size()) << "step " << k;
    for (const auto& [label, mean] : ea) {
      const auto it = eb.find(label);
      ASSERT_NE(it, eb.end()) << "step " << k;
      EXPECT_LT((it->second - mean).norm(), 1e-9) << "step " << k;
    }
    EXPECT_EQ(a.total_tracks(), b.total_tracks()) << "step " << k;
  }
  // the far part of the corridor was frozen at the turn and thawed on the way back; at the end (back at the
  // start) only tracks beyond the thaw radius are frozen
  EXPECT_GT(frozen_at_turn, 40u);
  EXPECT_GT(thaws, 5);
  const double r_thaw = model.query_radius() + freezing.freeze_margin;
  b.for_each_frozen([&](const Track<Model>& t) { EXPECT_GT(t.mean.norm(), r_thaw); });
  EXPECT_GT(b.frozen_count, 0u);
  // the live table stayed near the sensor: well below the ~62 landmarks of the corridor
  EXPECT_LT(max_live, max_frozen);
}

TEST(FrozenTracks, DisabledByDefault) {
  const Model model(corridor_sensor());
  const Updater updater(model, GlmbConfig{});
  Map m = Map::empty();
  for (int k = 0; k <= 60; ++k) {
    const Pose2 x(k, 0.0, 0.0);
    RandomStream sim(3, static_cast<std::uint64_t>(k)), rng(5, static_cast<std::uint64_t>(k));
    Map next;
    updater.update(m, x, simulate(model, x, corridor_landmarks(), sim), k, rng, next);
    m = std::move(next);
  }
  EXPECT_EQ(m.frozen_count, 0u);
  EXPECT_EQ(m.frozen, nullptr);
  EXPECT_GT(m.tracks.size(), 20u);
}

}  // namespace
}  // namespace glmbslam::backend
