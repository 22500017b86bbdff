#pragma once
// Optional appearance of landmarks (issue 7: ORB descriptors in the stereo model). A measurement model may
// declare `using Appearance = …` with
//   bool uses_appearance() const;                                  the term is switched on
//   Appearance measurement_appearance(int j) const;                appearance of measurement j of the current
//   set double log_appearance_ratio(const Appearance& landmark, int j) const;
//       log p(a_j | landmark) / p(a_j | clutter), multiplied into the single-landmark likelihood g(z_j | m)
//       (the clutter intensity κ(z) carries the clutter appearance density, hence the ratio).
// Models without it (the 2D ones) get NoAppearance and the δ-GLMB update compiles the term away.
#include <type_traits>

namespace glmbslam::backend {

struct NoAppearance {};

template <class Meas, class = void>
struct AppearanceOf {
  using Type = NoAppearance;
  static constexpr bool kEnabled = false;
};
template <class Meas>
struct AppearanceOf<Meas, std::void_t<typename Meas::Appearance>> {
  using Type = typename Meas::Appearance;
  static constexpr bool kEnabled = true;
};

}  // namespace glmbslam::backend
