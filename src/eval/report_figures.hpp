#pragma once
// The figures report.html shares between `run`, `vo` and `sim` (eval/html_report.hpp draws them): camera
// paths and the landmark map in 3D and from the top, errors along the path, KITTI errors per segment length,
// quantities over time, and the metrics JSON as a table.
//
// Camera poses are T_world_camera in the KITTI camera frame (x right, y down, z forward); the 3D view shows
// (x, z, −y) so "up" is up, the top view x against z.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/types.hpp"
#include "eval/html_report.hpp"
#include "eval/report.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::eval {

/// Line colours of the report (the PNG plots' Tableau palette).
namespace report_colours {
inline constexpr const char* kGroundTruth = "#000000";
inline constexpr const char* kVo = "#ff7f0e";
inline constexpr const char* kSlam = "#1f77b4";
inline constexpr const char* kRefined = "#2ca02c";
inline constexpr const char* kRed = "#d62728";
inline constexpr const char* kPurple = "#9467bd";
}  // namespace report_colours

/// A camera path to draw.
struct ReportPath {
  std::string name;
  const PoseList* poses = nullptr;
  std::string colour;
};

/// A path with its evaluation against the ground truth.
struct ReportEvaluation {
  std::string name;
  const TrajectoryEvaluation* evaluation = nullptr;
  std::string colour;
};

/// How map.pcd labels read: δ-GLMB labels pack birth frame << 12 | index; others are plain indices.
enum class LandmarkLabels { kPacked, kIndex };

/// Landmarks drawn at most in the 2D top view (every k-th beyond that; the 3D view draws all of them).
inline constexpr std::size_t kTopViewLandmarks = 20000;

/// Adds the 3D view (landmarks coloured by existence probability, hover: label, birth frame, existence;
/// the paths) and the top view. Paths with no pose are skipped.
void add_map_and_paths(HtmlReport& report, const std::vector<io::MapPoint>& map,
                       const std::vector<ReportPath>& paths, LandmarkLabels labels = LandmarkLabels::kPacked);

/// Adds the position error after SE(3) alignment along the ground-truth path and the KITTI t_rel / r_rel per
/// segment length (the standard lengths, or the short ones when no standard segment fits).
void add_trajectory_errors(HtmlReport& report, const PoseList& ground_truth,
                           const std::vector<ReportEvaluation>& evaluations);

/// A 2D series (path as a line, or points as markers) of a plane view.
struct ReportSeries2D {
  std::string name;
  std::vector<double> x, y;
  std::string colour;
  bool markers = false;
};

/// Adds a 2D view with equal axes: the landmarks of `map` (x, y) coloured by existence (hover: label and
/// existence), then `series`. For the 2D benchmarks (simulations, Victoria Park).
void add_plane_view(HtmlReport& report, const std::string& title, const std::vector<io::MapPoint>& map,
                    const std::vector<ReportSeries2D>& series,
                    LandmarkLabels labels = LandmarkLabels::kIndex);

/// A plotly line trace.
nlohmann::json line_trace(const std::string& name, const std::vector<double>& x, const std::vector<double>& y,
                          const std::string& colour);

/// 0, 1, …, n − 1 (+ first), as doubles (x axes over steps or frames).
std::vector<double> index_axis(std::size_t n, double first = 0.0);

/// Layout of a plot with the given axis titles.
nlohmann::json axes_layout(const std::string& x_title, const std::string& y_title);

/// The rows (key, value) of a JSON object flattened with dotted keys; arrays of more than `max_array` numbers
/// or `max_objects` objects (e.g. the per-length KITTI blocks, which the report plots) are summarised by
/// their size. Numbers with up to 6 significant digits.
std::vector<std::vector<std::string>> metrics_rows(const nlohmann::json& metrics, std::size_t max_array = 12,
                                                   std::size_t max_objects = 3);

/// A number with `digits` significant digits ("–" if not finite).
std::string format_number(double v, int digits = 6);

}  // namespace glmbslam::eval
