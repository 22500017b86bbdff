#pragma once
// The {mean, std, median, p95} block of a per-run quantity in the metrics.json files of `glmbslam sim`.
#include <vector>

#include <nlohmann/json.hpp>

#include "core/stopwatch.hpp"

namespace glmbslam::app {

inline nlohmann::json summary_json(const std::vector<double>& v) {
  const SampleSummary s = summarize(v);
  return nlohmann::json{{"mean", s.mean}, {"std", s.stddev}, {"median", s.median}, {"p95", s.p95}};
}

}  // namespace glmbslam::app
