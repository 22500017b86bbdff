// report.html: the page embeds the vendored plotly.js bundle byte for byte, its data survives the trip
// through the <script> element intact (escaping), and the shared figures carry what the report promises
// (landmark labels decoded, existence colours, paths, subsampled top view). The page drawing in a browser is
// tested in tests/app/test_report_html_browser.cpp.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "eval/html_report.hpp"
#include "eval/plotly_bundle.hpp"
#include "eval/report_figures.hpp"
#include "support/test_data.hpp"

namespace glmbslam::eval {
namespace {

using json = nlohmann::json;

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
  return n;
}

/// The report's data block parsed back from the page (JSON reads "<\/" as "</").
json report_data(const std::string& page) {
  const std::string open = "<script id=\"report-data\" type=\"application/json\">";
  const std::size_t begin = page.find(open);
  EXPECT_NE(begin, std::string::npos);
  const std::size_t end = page.find("</script>", begin);
  return json::parse(page.substr(begin + open.size(), end - begin - open.size()));
}

std::vector<json> plots(const json& data) {
  std::vector<json> out;
  for (const auto& b : data["blocks"]) {
    if (b["kind"] == "plot") out.push_back(b);
  }
  return out;
}

TEST(PlotlyBundle, IsTheVendoredFileByteForByte) {
  const std::filesystem::path vendored =
      std::filesystem::path(GLMBSLAM_SOURCE_DIR) / "third_party" / "plotly.js" / "plotly-gl3d.min.js";
  const std::string file = read_file(vendored);
  ASSERT_GT(file.size(), 1000000u) << vendored;
  EXPECT_TRUE(plotly_bundle() == file) << "the compiled-in bundle differs from " << vendored;
  // The version the README records.
  const std::string readme = read_file(vendored.parent_path() / "README.md");
  EXPECT_EQ(plotly_bundle_version(), "4.1.1");
  EXPECT_NE(readme.find("Version: " + std::string(plotly_bundle_version()) + "."), std::string::npos);
  // Safe to inline in a <script> element as it is: nothing in it ends the element or opens a comment.
  std::string lower = file;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  EXPECT_EQ(lower.find("</script"), std::string::npos);
  EXPECT_EQ(lower.find("<!--"), std::string::npos);
}

TEST(EscapeJsonForScript, NoLessThanSignLeftAndTheValueIsUnchanged) {
  const json value = {{"a", "x</script><!--y<b>"}, {"b", {1, 2}}};
  const std::string escaped = escape_json_for_script(value.dump());
  EXPECT_EQ(escaped.find('<'), std::string::npos);
  EXPECT_EQ(json::parse(escaped), value);
}

TEST(HtmlReport, PageHoldsBundleDataAndExactlyFourScripts) {
  HtmlReport r("Title </script><script>alert(1)</script>", "sub & title");
  r.add_section("Section", "note");
  r.add_plot("plot",
             json::array({line_trace("a", {0, 1}, {2, 3}, "#000"), line_trace("b", {0}, {1}, "#111")}));
  r.add_table("table", {"k", "v"}, {{"x", "</script>"}});
  r.add_text("config", "key: value\n<!-- not a comment -->\n");
  EXPECT_EQ(r.plot_count(), 1u);
  EXPECT_EQ(r.trace_count(), 2u);
  const std::string page = r.html();
  // error capture, plotly, data, page script: no text closes an element early
  EXPECT_EQ(count(page, "<script"), 4u);
  EXPECT_EQ(count(page, "</script>"), 4u);
  EXPECT_NE(page.find(std::string(plotly_bundle())), std::string::npos);
  EXPECT_NE(page.find("<title>Title &lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;</title>"),
            std::string::npos);
  const json data = report_data(page);
  EXPECT_EQ(data["title"], "Title </script><script>alert(1)</script>");
  ASSERT_EQ(data["blocks"].size(), 4u);
  EXPECT_EQ(data["blocks"][2]["rows"][0][1], "</script>");
  EXPECT_EQ(data["blocks"][3]["text"], "key: value\n<!-- not a comment -->\n");
  EXPECT_EQ(data["blocks"][1]["data"].size(), 2u);
}

TEST(HtmlReport, RejectsMalformedBlocks) {
  HtmlReport r("t");
  EXPECT_THROW(r.add_plot("p", json::object()), std::invalid_argument);
  EXPECT_THROW(r.add_plot("p", json::array(), json::array()), std::invalid_argument);
  EXPECT_THROW(r.add_table("t", {"a", "b"}, {{"1"}}), std::invalid_argument);
}

TEST(HtmlReport, NonFiniteNumbersBecomeGaps) {
  HtmlReport r("t");
  r.add_plot("p", json::array({line_trace("a", {0, 1, 2}, {1, std::nan(""), 3}, "#000")}));
  const json data = report_data(r.html());
  EXPECT_TRUE(data["blocks"][0]["data"][0]["y"][1].is_null());
}

TEST(HtmlReport, WritesTheFileAtomically) {
  const auto dir = test::fresh_temp_dir("report_html");
  HtmlReport r("t");
  r.write((dir / "report.html").string());
  EXPECT_EQ(read_file(dir / "report.html"), r.html());
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()),
            1);
  std::filesystem::remove_all(dir);
}

TEST(ReportFigures, MapLabelsExistenceAndPaths) {
  std::vector<io::MapPoint> map = {{Eigen::Vector3d(1.0, -2.0, 3.0), (std::uint64_t{37} << 12) | 5u, 0.25},
                                   {Eigen::Vector3d(4.0, 5.0, 6.0), (std::uint64_t{0} << 12) | 9u, 1.0}};
  PoseList path(3, Pose3::Identity());
  path[1].translation() = Eigen::Vector3d(0.5, -1.0, 2.0);
  path[2].translation() = Eigen::Vector3d(1.0, -1.0, 4.0);
  const PoseList empty;
  HtmlReport r("t");
  add_map_and_paths(r, map, {{"slam", &path, "#1f77b4"}, {"none", &empty, "#000"}});
  const auto p = plots(report_data(r.html()));
  ASSERT_EQ(p.size(), 2u);  // 3D and top view
  const json& lm = p[0]["data"][0];
  EXPECT_EQ(lm["type"], "scatter3d");
  // (x, z, −y): up is up
  EXPECT_EQ(lm["x"][0], 1.0);
  EXPECT_EQ(lm["y"][0], 3.0);
  EXPECT_EQ(lm["z"][0], 2.0);
  // label, birth frame, index, existence
  EXPECT_EQ(lm["customdata"][0], json::array({(37 << 12) | 5, 37, 5, 0.25}));
  EXPECT_EQ(lm["customdata"][1], json::array({9, 0, 9, 1.0}));
  EXPECT_EQ(lm["marker"]["color"], json::array({0.25, 1.0}));
  EXPECT_EQ(lm["marker"]["cmin"], 0.0);
  EXPECT_EQ(lm["marker"]["cmax"], 1.0);
  ASSERT_EQ(p[0]["data"].size(), 2u);  // the empty path is left out
  EXPECT_EQ(p[0]["data"][1]["name"], "slam");
  EXPECT_EQ(p[0]["data"][1]["z"], json::array({0.0, 1.0, 1.0}));
  EXPECT_EQ(p[1]["data"][1]["y"], json::array({0.0, 2.0, 4.0}));  // top view: x against z
}

TEST(ReportFigures, TopViewSubsamplesLargeMapsThe3DViewDoesNot) {
  std::vector<io::MapPoint> map(kTopViewLandmarks * 2 + 1);
  HtmlReport r("t");
  add_map_and_paths(r, map, {});
  const auto p = plots(report_data(r.html()));
  EXPECT_EQ(p[0]["data"][0]["x"].size(), map.size());
  EXPECT_LE(p[1]["data"][0]["x"].size(), kTopViewLandmarks);
  EXPECT_GE(p[1]["data"][0]["x"].size(), kTopViewLandmarks * 9 / 10);
}

TEST(ReportFigures, TrajectoryErrorsFollowTheEvaluation) {
  PoseList gt, est;
  for (int k = 0; k < 300; ++k) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(0.0, 0.0, 1.0 * k);
    gt.push_back(T);
    T.translation().x() = 0.01 * k;
    est.push_back(T);
  }
  const TrajectoryEvaluation e = evaluate_trajectory(gt, est);
  HtmlReport r("t");
  add_trajectory_errors(r, gt, {{"est", &e, "#000"}});
  const auto p = plots(report_data(r.html()));
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0]["data"][0]["y"].size(), e.ate.se3_errors_m.size());
  EXPECT_DOUBLE_EQ(p[0]["data"][0]["x"][299].get<double>(), 299.0);  // distance along the ground truth
  ASSERT_EQ(p[1]["data"][0]["x"].size(), e.kitti.per_length.size());
  EXPECT_DOUBLE_EQ(p[1]["data"][0]["y"][0].get<double>(), e.kitti.per_length[0].t_rel_percent);
  EXPECT_DOUBLE_EQ(p[2]["data"][0]["y"][0].get<double>(), e.kitti.per_length[0].r_rel_deg_per_100m);
}

TEST(ReportFigures, MetricsRowsFlattenWithDottedKeys) {
  const json m = {{"a", 1.23456789},
                  {"b", {{"c", "x"}, {"d", nullptr}}},
                  {"v", {1, 2}},
                  {"long", std::vector<double>(20, 0.0)},
                  {"blocks", json::array({{{"k", 1}}, {{"k", 2}}, {{"k", 3}}, {{"k", 4}}})}};
  const auto rows = metrics_rows(m);
  const std::vector<std::vector<std::string>> expected = {
      {"a", "1.23457"},      {"b.c", "x"}, {"b.d", "–"}, {"blocks", "4 entries (in the JSON file)"},
      {"long", "20 values"}, {"v", "1, 2"}};
  EXPECT_EQ(rows, expected);
}

}  // namespace
}  // namespace glmbslam::eval
