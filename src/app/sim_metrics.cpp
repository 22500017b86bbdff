#include "app/sim_metrics.hpp"

#include <algorithm>
#include <cmath>

#include "app/sample_summary_json.hpp"
#include "app/sim_map_scoring.hpp"
#include "core/lie.hpp"
#include "core/parallel.hpp"

namespace glmbslam::app {

namespace {

using json = nlohmann::json;

constexpr double kRad2Deg = 180.0 / M_PI;

/// Sums and per-run lists over the finished runs.
struct RunStatistics {
  SimStepCurves curves;
  std::vector<double> gospa_mean, card_mean;  // per step (paper2019), k = 1..K−1
  std::vector<double> per_run_pos, per_run_head, ms_all, ess_all, final_ospa, gospa_d, gospa_loc, gospa_miss,
      gospa_false, card_err;
  std::vector<double> filter_rmse, filter_gospa, ml_ms;  // --refine ml / mlslam
  double se_pos = 0.0, se_head = 0.0;
  std::size_t n_err = 0, resampled = 0, steps_total = 0;
};

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

/// The mean, or null when nothing was measured (RFS-ML from the odometry has no per-step maps and no
/// particle weights: its per-step OSPA and ESS do not exist, they are not 0).
json mean_or_null(const std::vector<double>& v) {
  return v.empty() ? json(nullptr) : json(mean_of(v));
}

RunStatistics aggregate(const std::vector<SimRunRecord>& records, const sim::Scenario2D& truth) {
  const std::size_t runs = records.size(), K = truth.steps();
  RunStatistics st;
  SimStepCurves& c = st.curves;  // rmse_*: sums of squares until the end
  c.rmse_x.assign(K, 0.0);
  c.rmse_y.assign(K, 0.0);
  c.rmse_h.assign(K, 0.0);
  for (const SimRunRecord& rec : records) {
    double run_pos = 0.0, run_head = 0.0;
    for (std::size_t k = 0; k < K; ++k) {
      const Eigen::Vector3d& e = rec.estimates[k];
      const double dx = e(0) - truth.poses[k](0), dy = e(1) - truth.poses[k](1);
      const double dh = wrap_angle(e(2) - truth.poses[k](2));
      c.rmse_x[k] += dx * dx;
      c.rmse_y[k] += dy * dy;
      c.rmse_h[k] += dh * dh;
      if (k > 0) {
        st.se_pos += dx * dx + dy * dy;
        st.se_head += dh * dh;
        run_pos += dx * dx + dy * dy;
        run_head += dh * dh;
        ++st.n_err;
      }
    }
    st.per_run_pos.push_back(std::sqrt(run_pos / static_cast<double>(K - 1)));
    st.per_run_head.push_back(std::sqrt(run_head / static_cast<double>(K - 1)) * kRad2Deg);
    st.ms_all.insert(st.ms_all.end(), rec.ms.begin(), rec.ms.end());
    for (double e : rec.ess_fraction) st.ess_all.push_back(100.0 * e);
    st.resampled += static_cast<std::size_t>(rec.resampled);
    st.steps_total += rec.ms.size();
    st.final_ospa.push_back(rec.final_ospa.distance);
    st.gospa_d.push_back(rec.final_gospa.distance);
    st.gospa_loc.push_back(rec.final_gospa.localisation);
    st.gospa_miss.push_back(rec.final_gospa.missed);
    st.gospa_false.push_back(rec.final_gospa.false_);
    st.card_err.push_back(static_cast<double>(rec.final_cardinality_error));
    st.filter_rmse.push_back(rec.filter_position_rmse);
    st.filter_gospa.push_back(rec.filter_gospa);
    st.ml_ms.push_back(rec.ml_ms);
    if (!rec.ospa.empty()) {
      if (c.ospa_mean.empty()) c.ospa_mean.assign(rec.ospa.size(), 0.0);
      st.gospa_mean.resize(rec.ospa.size(), 0.0);
      st.card_mean.resize(rec.ospa.size(), 0.0);
      for (std::size_t k = 0; k < rec.ospa.size(); ++k) {
        c.ospa_mean[k] += rec.ospa[k] / static_cast<double>(runs);
        st.gospa_mean[k] += rec.gospa[k] / static_cast<double>(runs);
        st.card_mean[k] += rec.cardinality[k] / static_cast<double>(runs);
      }
    }
  }
  for (std::size_t k = 0; k < K; ++k) {
    c.rmse_x[k] = std::sqrt(c.rmse_x[k] / static_cast<double>(runs));
    c.rmse_y[k] = std::sqrt(c.rmse_y[k] / static_cast<double>(runs));
    c.rmse_h[k] = std::sqrt(c.rmse_h[k] / static_cast<double>(runs)) * kRad2Deg;
  }
  return st;
}

/// paper2019: the mean map OSPA per step against the landmarks seen so far (paper 000); otherwise the final
/// map's GOSPA (paper 003) and OSPA.
void add_map_metrics(json& m, const SimOptions& o, const sim::Scenario2D& truth, const RunStatistics& st) {
  if (o.scenario == "paper2019") {
    m["ospa"] =
        json{{"c_m", kSimOspaC},
             {"p", kSimOspaP},
             {"per_step_mean_m", st.curves.ospa_mean},
             {"mean_over_steps_m", mean_or_null(st.curves.ospa_mean)},
             {"per_step_gospa_mean_m", st.gospa_mean},
             {"gospa_mean_over_steps_m", mean_or_null(st.gospa_mean)},
             {"final_m", summary_json(st.final_ospa)},
             {"ground_truth", "landmarks seen (in the field of view of the true pose) up to the step"}};
    const auto seen = seen_so_far(truth);
    std::vector<double> true_card;
    for (std::size_t k = 1; k < truth.steps(); ++k) true_card.push_back(static_cast<double>(seen[k].size()));
    m["cardinality_per_step"] = json{{"estimated_mean", st.card_mean}, {"true", true_card}};
  } else {
    m["gospa"] =
        json{{"c_m", kSimGospaC},
             {"p", kSimGospaP},
             {"alpha", 2.0},
             {"distance_m", summary_json(st.gospa_d)},
             {"distance_each_run_m", st.gospa_d},
             {"localisation_m2", summary_json(st.gospa_loc)},
             {"missed_m2", summary_json(st.gospa_miss)},
             {"false_m2", summary_json(st.gospa_false)},
             {"ground_truth", "landmarks seen during the run, final map of the highest-weight particle"}};
    m["ospa_final_m"] = summary_json(st.final_ospa);
  }
  std::vector<double> abs_card;
  for (double c : st.card_err) abs_card.push_back(std::abs(c));
  m["cardinality_error"] = json{{"mean", mean_of(st.card_err)}, {"mean_abs", mean_of(abs_card)}};
}

/// --refine ml / mlslam: the solve's time and, for a refinement, the filter's errors before it.
void add_ml_metrics(json& m, const SimOptions& o, const RunStatistics& st) {
  if (o.refine != "ml" && o.algorithm != "mlslam") return;
  m["ml"] = json{{"ms_per_run", summary_json(st.ml_ms)}};
  if (o.refine == "ml") {
    m["ml"]["filter_position_rmse_per_run_m"] = summary_json(st.filter_rmse);
    m["ml"]["filter_position_rmse_each_run_m"] = st.filter_rmse;
    if (m.contains("gospa")) {
      m["ml"]["filter_gospa_m"] = summary_json(st.filter_gospa);
      m["ml"]["filter_gospa_each_run_m"] = st.filter_gospa;
    }
  }
  m["refine"] = o.refine;
}

}  // namespace

json no_runs_metrics(const SimOptions& o, const SimRuns& runs) {
  return json{{"scenario", o.scenario},
              {"algorithm", o.algorithm},
              {"particles", *o.particles},
              {"runs", 0},
              {"runs_requested", runs.requested},
              {"run_indices", runs.run_indices},
              {"interrupted", true},
              {"wall_time_s", runs.wall_s}};
}

SimMetrics sim_metrics(const SimOptions& o, const SimRuns& runs, const sim::Scenario2D& truth,
                       double clutter_rate) {
  const RunStatistics st = aggregate(runs.records, truth);
  json m;
  m["scenario"] = o.scenario;
  m["algorithm"] = o.algorithm;
  m["particles"] = *o.particles;
  m["runs"] = runs.records.size();
  m["runs_requested"] = runs.requested;
  m["run_indices"] = runs.run_indices;
  m["interrupted"] = runs.interrupted();
  m["first_run"] = o.first_run;
  m["clutter_rate"] = clutter_rate;
  m["seed"] = *o.seed;
  m["steps"] = truth.steps();
  m["threads"] = thread_count();
  m["wall_time_s"] = runs.wall_s;
  m["position_rmse_m"] = std::sqrt(st.se_pos / static_cast<double>(std::max<std::size_t>(st.n_err, 1)));
  m["heading_rmse_deg"] =
      std::sqrt(st.se_head / static_cast<double>(std::max<std::size_t>(st.n_err, 1))) * kRad2Deg;
  m["position_rmse_per_run_m"] = summary_json(st.per_run_pos);
  m["heading_rmse_per_run_deg"] = summary_json(st.per_run_head);
  m["position_rmse_each_run_m"] = st.per_run_pos;  // entry i: run run_indices[i] (= data realisation)
  m["rmse_per_step"] =
      json{{"x_m", st.curves.rmse_x}, {"y_m", st.curves.rmse_y}, {"heading_deg", st.curves.rmse_h}};
  add_map_metrics(m, o, truth, st);
  add_ml_metrics(m, o, st);
  m["ms_per_step"] = summary_json(st.ms_all);
  m["ess_percent"] = mean_or_null(st.ess_all);
  m["resampling_percent"] =
      st.ess_all.empty() || st.steps_total == 0
          ? json(nullptr)
          : json(100.0 * static_cast<double>(st.resampled) / static_cast<double>(st.steps_total));
  return {m, st.curves};
}

}  // namespace glmbslam::app
