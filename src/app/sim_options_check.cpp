#include "app/sim_options_check.hpp"

#include <algorithm>
#include <string>

#include "app/refine_flag.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace glmbslam::app {

namespace {

template <std::size_t N>
bool is_one_of(const std::string& value, const std::array<std::string_view, N>& names) {
  return std::find(names.begin(), names.end(), value) != names.end();
}

/// "a, b or c".
template <std::size_t N>
std::string alternatives(const std::array<std::string_view, N>& names) {
  std::string s;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) s += i + 1 == N ? " or " : ", ";
    s += names[i];
  }
  return s;
}

}  // namespace

void check_sim_options(const SimOptions& o) {
  if (!is_one_of(o.scenario, kSimScenarios))
    throw ConfigError("--scenario must be " + alternatives(kSimScenarios) + ", got '" + o.scenario + "'");
  if (!o.refine.empty() && o.refine != "ml") throw ConfigError("--refine must be ml, got '" + o.refine + "'");
  if (!is_one_of(o.algorithm, kSimAlgorithms))
    throw ConfigError("--algorithm must be " + alternatives(kSimAlgorithms) + ", got '" + o.algorithm + "'");
  if (*o.particles < 1) throw ConfigError("--particles must be at least 1");
  if (o.algorithm == "mlslam" && !o.refine.empty()) {
    throw ConfigError(kMlslamTakesNoRefinement);
  }
  if (o.runs < 1) throw ConfigError("--runs must be at least 1");
  if (o.first_run < 0) throw ConfigError("--first-run must not be negative");
  if (o.out_dir.empty()) throw ConfigError("--out is required");
  ensure_writable_directory(o.out_dir);
  if (o.scenario == "paper004_1d") {
    // paper 004's 1D problem has no filter: RFS-ML (or its vector baseline) from the odometry only
    if (o.algorithm != "mlslam")
      throw ConfigError(
          "--scenario paper004_1d needs --algorithm mlslam (RFS-ML from the odometry; the 1D "
          "problem has no filter), got '" +
          o.algorithm + "'");
    if (!o.refine.empty()) throw ConfigError("--scenario paper004_1d has no filter to --refine");
  }
}

}  // namespace glmbslam::app
