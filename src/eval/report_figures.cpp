#include "eval/report_figures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>

#include "eval/kitti_metric.hpp"

namespace glmbslam::eval {
namespace {

using json = nlohmann::json;

/// Rounded to a millimetre (keeps the page small; far below any error the report shows).
double mm(double v) {
  return std::round(v * 1000.0) / 1000.0;
}

json path_trace_3d(const ReportPath& p) {
  json x = json::array(), y = json::array(), z = json::array();
  for (const auto& T : *p.poses) {
    x.push_back(mm(T.translation().x()));
    y.push_back(mm(T.translation().z()));
    z.push_back(mm(-T.translation().y()));
  }
  return {{"type", "scatter3d"},
          {"mode", "lines"},
          {"name", p.name},
          {"x", std::move(x)},
          {"y", std::move(y)},
          {"z", std::move(z)},
          {"line", {{"color", p.colour}, {"width", 4}}}};
}

json path_trace_top(const ReportPath& p) {
  std::vector<double> x, z;
  for (const auto& T : *p.poses) {
    x.push_back(mm(T.translation().x()));
    z.push_back(mm(T.translation().z()));
  }
  return line_trace(p.name, x, z, p.colour);
}

json landmark_customdata(const io::MapPoint& m, LandmarkLabels labels) {
  const double existence = std::round(m.existence * 1000.0) / 1000.0;
  if (labels == LandmarkLabels::kPacked) return {m.label, m.label >> 12, m.label & 0xFFFu, existence};
  return {m.label, existence};
}

std::string landmark_hover(LandmarkLabels labels) {
  if (labels == LandmarkLabels::kPacked)
    return "label %{customdata[0]}<br>birth frame %{customdata[1]}, index %{customdata[2]}<br>"
           "existence %{customdata[3]}<extra></extra>";
  return "landmark %{customdata[0]}<br>existence %{customdata[1]}<extra></extra>";
}

json colour_by_existence(json existence, bool colour_bar) {
  json marker = {{"size", 2},   {"color", std::move(existence)}, {"colorscale", "Viridis"}, {"cmin", 0.0},
                 {"cmax", 1.0}, {"showscale", colour_bar}};
  if (colour_bar) marker["colorbar"] = {{"title", {{"text", "existence"}}}, {"thickness", 14}};
  return marker;
}

/// Landmarks `indices` of `map` as one marker trace coloured by existence; `plotted` maps a position to the
/// drawn coordinates (x, y, and z for a scatter3d trace).
json landmark_trace(const std::string& type, const std::string& name, const std::vector<io::MapPoint>& map,
                    const std::vector<std::size_t>& indices,
                    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& plotted,
                    LandmarkLabels labels, bool colour_bar, int size) {
  json x = json::array(), y = json::array(), z = json::array(), existence = json::array(),
       custom = json::array();
  for (std::size_t i : indices) {
    const Eigen::Vector3d p = plotted(map[i].position);
    x.push_back(mm(p.x()));
    y.push_back(mm(p.y()));
    z.push_back(mm(p.z()));
    existence.push_back(std::round(map[i].existence * 1000.0) / 1000.0);
    custom.push_back(landmark_customdata(map[i], labels));
  }
  json marker = colour_by_existence(std::move(existence), colour_bar);
  marker["size"] = size;
  json trace = {{"type", type},
                {"mode", "markers"},
                {"name", name},
                {"x", std::move(x)},
                {"y", std::move(y)},
                {"customdata", std::move(custom)},
                {"hovertemplate", landmark_hover(labels)},
                {"marker", std::move(marker)}};
  if (type == "scatter3d") trace["z"] = std::move(z);
  return trace;
}

std::vector<std::size_t> all_indices(std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

}  // namespace

std::string format_number(double v, int digits) {
  if (!std::isfinite(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::vector<double> index_axis(std::size_t n, double first) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = first + static_cast<double>(i);
  return x;
}

json line_trace(const std::string& name, const std::vector<double>& x, const std::vector<double>& y,
                const std::string& colour) {
  return {{"type", "scatter"},
          {"mode", "lines"},
          {"name", name},
          {"x", x},
          {"y", y},
          {"line", {{"color", colour}, {"width", 2}}}};
}

json axes_layout(const std::string& x_title, const std::string& y_title) {
  return {{"xaxis", {{"title", {{"text", x_title}}}}}, {"yaxis", {{"title", {{"text", y_title}}}}}};
}

void add_map_and_paths(HtmlReport& report, const std::vector<io::MapPoint>& map,
                       const std::vector<ReportPath>& paths, LandmarkLabels labels) {
  std::vector<ReportPath> drawn;
  for (const auto& p : paths) {
    if (p.poses && !p.poses->empty()) drawn.push_back(p);
  }
  // 3D: every landmark, shown as (x, z, −y).
  json traces3d = json::array();
  if (!map.empty())
    traces3d.push_back(landmark_trace(
        "scatter3d", "landmarks (" + std::to_string(map.size()) + ")", map, all_indices(map.size()),
        [](const Eigen::Vector3d& p) { return Eigen::Vector3d(p.x(), p.z(), -p.y()); }, labels, true, 2));
  for (const auto& p : drawn) traces3d.push_back(path_trace_3d(p));
  const json scene = {{"aspectmode", "data"},
                      {"xaxis", {{"title", {{"text", "x right [m]"}}}}},
                      {"yaxis", {{"title", {{"text", "z forward [m]"}}}}},
                      {"zaxis", {{"title", {{"text", "up [m]"}}}}},
                      {"camera", {{"eye", {{"x", 0.9}, {"y", -1.6}, {"z", 1.3}}}}}};
  report.add_plot(map.empty()
                      ? "Camera paths (3D: drag to rotate, scroll to zoom)"
                      : "Map and camera paths (3D: drag to rotate, scroll to zoom; landmarks coloured "
                        "by existence)",
                  std::move(traces3d), {{"scene", scene}, {"legend", {{"x", 0.0}, {"y", 1.0}}}}, 700);

  // Top view: at most kTopViewLandmarks landmarks (SVG).
  const std::size_t shown = std::min(map.size(), kTopViewLandmarks);
  std::vector<std::size_t> spread(shown);
  for (std::size_t j = 0; j < shown; ++j) spread[j] = j * map.size() / shown;  // evenly over the map
  json top = json::array();
  if (!map.empty())
    top.push_back(landmark_trace(
        "scatter",
        shown < map.size() ? "landmarks (" + std::to_string(shown) + " of " + std::to_string(map.size()) + ")"
                           : "landmarks",
        map, spread, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(p.x(), p.z(), 0.0); }, labels,
        false, 2));
  for (const auto& p : drawn) top.push_back(path_trace_top(p));
  json layout = axes_layout("x right [m]", "z forward [m]");
  layout["yaxis"]["scaleanchor"] = "x";
  report.add_plot("Top view", std::move(top), std::move(layout), 650);
}

void add_trajectory_errors(HtmlReport& report, const PoseList& ground_truth,
                           const std::vector<ReportEvaluation>& evaluations) {
  const std::vector<float> along = trajectory_distances(ground_truth);
  const std::vector<double> distance(along.begin(), along.end());
  json errors = json::array();
  for (const auto& e : evaluations) {
    errors.push_back(line_trace(e.name, distance, e.evaluation->ate.se3_errors_m, e.colour));
  }
  report.add_plot("Position error along the path (after SE(3) alignment)", std::move(errors),
                  axes_layout("distance along the ground truth [m]", "position error [m]"));

  json t_rel = json::array(), r_rel = json::array();
  std::string lengths = "standard";
  for (const auto& e : evaluations) {
    const bool standard = e.evaluation->kitti.segments > 0;
    if (!standard) lengths = "short";
    const KittiResult& k = standard ? e.evaluation->kitti : e.evaluation->kitti_short;
    std::vector<double> len, t, r;
    for (const auto& l : k.per_length) {
      len.push_back(l.length_m);
      t.push_back(l.t_rel_percent);
      r.push_back(l.r_rel_deg_per_100m);
    }
    json tt = line_trace(e.name, len, t, e.colour), rt = line_trace(e.name, len, r, e.colour);
    tt["mode"] = rt["mode"] = "lines+markers";
    t_rel.push_back(std::move(tt));
    r_rel.push_back(std::move(rt));
  }
  report.add_plot("KITTI translation error per segment length (" + lengths + " lengths)", std::move(t_rel),
                  axes_layout("segment length [m]", "t_rel [%]"), 380);
  report.add_plot("KITTI rotation error per segment length (" + lengths + " lengths)", std::move(r_rel),
                  axes_layout("segment length [m]", "r_rel [deg/100 m]"), 380);
}

void add_plane_view(HtmlReport& report, const std::string& title, const std::vector<io::MapPoint>& map,
                    const std::vector<ReportSeries2D>& series, LandmarkLabels labels) {
  json traces = json::array();
  if (!map.empty())
    traces.push_back(landmark_trace(
        "scatter", "map (" + std::to_string(map.size()) + ")", map, all_indices(map.size()),
        [](const Eigen::Vector3d& p) { return p; }, labels, true, 5));
  for (const auto& s : series) {
    json t = line_trace(s.name, s.x, s.y, s.colour);
    if (s.markers) {
      t["mode"] = "markers";
      t["marker"] = {{"color", s.colour}, {"size", 4}};
    }
    traces.push_back(std::move(t));
  }
  json layout = axes_layout("x [m]", "y [m]");
  layout["yaxis"]["scaleanchor"] = "x";
  layout["legend"] = {
      {"x", 0.01}, {"y", 0.99}, {"bgcolor", "rgba(255,255,255,0.7)"}};  // clear of the colour bar
  report.add_plot(title, std::move(traces), std::move(layout), 650);
}

std::vector<std::vector<std::string>> metrics_rows(const nlohmann::json& metrics, std::size_t max_array,
                                                   std::size_t max_objects) {
  std::vector<std::vector<std::string>> rows;
  auto visit = [&](const auto& self, const json& j, const std::string& key) -> void {
    if (j.is_object()) {
      for (auto it = j.begin(); it != j.end(); ++it)
        self(self, it.value(), key.empty() ? it.key() : key + "." + it.key());
    } else if (j.is_array() && !j.empty() && j.front().is_object() && j.size() > max_objects) {
      rows.push_back({key, std::to_string(j.size()) + " entries (in the JSON file)"});
    } else if (j.is_array() && !j.empty() && j.front().is_object()) {
      for (std::size_t i = 0; i < j.size(); ++i) self(self, j[i], key + "[" + std::to_string(i) + "]");
    } else if (j.is_array() && j.size() > max_array) {
      rows.push_back({key, std::to_string(j.size()) + " values"});
    } else if (j.is_array()) {
      std::string s;
      for (const auto& v : j)
        s += (s.empty() ? "" : ", ") + (v.is_number() ? format_number(v.get<double>()) : v.dump());
      rows.push_back({key, s});
    } else if (j.is_number_float()) {
      rows.push_back({key, format_number(j.get<double>())});
    } else if (j.is_string()) {
      rows.push_back({key, j.get<std::string>()});
    } else {
      rows.push_back({key, j.is_null() ? "–" : j.dump()});
    }
  };
  visit(visit, metrics, "");
  return rows;
}

}  // namespace glmbslam::eval
