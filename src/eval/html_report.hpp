#pragma once
// report.html: one self-contained page (the vendored plotly.js bundle, the report's data as JSON and a small
// page script inlined) that opens offline in any browser. A report is a list of blocks drawn in order:
// section headings, interactive plotly plots (traces and layout as plotly JSON), tables and preformatted
// text (e.g. the effective configuration).
//
// The page marks itself for automated checks: when every plot has been drawn, <body> gets
// data-status="ready" (or "failed"), data-plots, data-expected-traces (traces in the data), data-traces
// (traces the browser drew: SVG trace groups of 2D plots, WebGL objects of 3D scenes) and data-errors (script
// errors and console.error calls since the page started); each plot's <div class="plot"> gets data-traces.
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace glmbslam::eval {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title, std::string subtitle = "");

  /// A heading (listed in the page's table of contents) with an optional note under it.
  void add_section(const std::string& heading, const std::string& note = "");
  /// A plotly plot: `traces` a JSON array of plotly traces, `layout` a plotly layout object (the title is
  /// set from `title`). Throws std::invalid_argument if `traces` is not an array.
  void add_plot(const std::string& title, nlohmann::json traces,
                nlohmann::json layout = nlohmann::json::object(), int height_px = 450);
  /// A table of preformatted cells; each row must have the header's size (std::invalid_argument otherwise).
  void add_table(const std::string& caption, std::vector<std::string> header,
                 std::vector<std::vector<std::string>> rows);
  /// Preformatted text shown in a collapsible box (open unless `collapsed`).
  void add_text(const std::string& caption, const std::string& text, bool collapsed = false);

  std::size_t plot_count() const { return plots_; }
  std::size_t trace_count() const { return traces_; }

  /// The complete page.
  std::string html() const;
  /// Writes html() to `path` atomically (streamed: the page is never held in memory whole); throws
  /// InputError naming the file on failure.
  void write(const std::string& path) const;

 private:
  void write_page(std::ostream& out) const;

  std::string title_, subtitle_;
  nlohmann::json blocks_ = nlohmann::json::array();
  std::size_t plots_ = 0, traces_ = 0;
};

/// JSON text made safe inside an HTML <script> element: every '<' (only ever inside JSON strings) becomes the
/// JSON escape \u003c, so no "</script" or "<!--" can end the element or open a comment; parsing gives the
/// same value.
std::string escape_json_for_script(const std::string& json);

}  // namespace glmbslam::eval
