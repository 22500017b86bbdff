#include "sim/scenario_paper004_line.hpp"

#include <cmath>

#include "core/random.hpp"

namespace glmbslam::sim {

namespace {

constexpr int kSteps = 50;
constexpr double kStep = 0.06;                   // true displacement per step (m): 0 → 2.94 m
constexpr double kPaperClutterIntensity = 0.01;  // per metre of the sensor's interval

}  // namespace

LineScenario make_paper004_line_scenario(const Paper004LineOptions& o) {
  LineScenario s;
  s.clutter_rate =
      o.clutter_rate >= 0.0 ? o.clutter_rate : kPaperClutterIntensity * (s.max_range - s.min_range);
  for (int k = 0; k < kSteps; ++k) s.poses.push_back(kStep * k);
  RandomStream layout(4, 1);
  for (int i = 0; i < 5; ++i) s.landmarks.push_back(3.5 + i + layout.uniform(-0.3, 0.3));

  RandomStream data(o.data_seed, 2);
  const double sigma_u = std::sqrt(s.odometry_variance), sigma_z = std::sqrt(s.measurement_variance);
  s.controls.push_back(0.0);
  for (int k = 1; k < kSteps; ++k) s.controls.push_back(kStep + sigma_u * data.normal());
  for (const double x : s.poses) {
    std::vector<double> z;
    std::vector<int> src;
    for (std::size_t i = 0; i < s.landmarks.size(); ++i) {
      const double offset = s.landmarks[i] - x;
      if (offset < s.min_range || offset > s.max_range) continue;
      if (data.uniform() >= s.detection_probability) continue;
      z.push_back(offset + sigma_z * data.normal());
      src.push_back(static_cast<int>(i));
    }
    for (int c = data.poisson(s.clutter_rate); c > 0; --c) {
      z.push_back(data.uniform(s.min_range, s.max_range));
      src.push_back(-1);
    }
    s.measurements.push_back(std::move(z));
    s.measurement_sources.push_back(std::move(src));
  }
  return s;
}

}  // namespace glmbslam::sim
