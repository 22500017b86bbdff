#pragma once
// report.html of the stereo commands (eval/html_report.hpp): `run` (map, SLAM/VO/refined/ground-truth paths,
// errors, filter state over time, metrics, effective config) and `vo` (VO path, errors, tracking over time).
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/run_outputs.hpp"
#include "eval/report.hpp"

namespace glmbslam::app {

/// The report of a stereo `run`; `slam`, `vo` and `refined` are the evaluations (null without ground truth;
/// `refined` also without --refine ml).
void write_run_report(const std::string& path, const RunRecord& record, const nlohmann::json& metrics,
                      const eval::TrajectoryEvaluation* slam, const eval::TrajectoryEvaluation* vo,
                      const eval::TrajectoryEvaluation* refined = nullptr);

/// What `glmbslam vo` reports.
struct VoReportInput {
  std::string dataset;
  std::size_t first_frame = 0;
  const PoseList* poses = nullptr;
  const std::optional<PoseList>* ground_truth = nullptr;   ///< relative to the first frame of the range
  const eval::TrajectoryEvaluation* evaluation = nullptr;  ///< null without ground truth
  std::vector<double> measurements, matches, inliers;      ///< per frame
  std::string config;                                      ///< the config file's text, or empty (defaults)
};

/// The report of `glmbslam vo`.
void write_vo_report(const std::string& path, const VoReportInput& input, const nlohmann::json& metrics);

}  // namespace glmbslam::app
