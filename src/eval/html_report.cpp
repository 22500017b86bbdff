#include "eval/html_report.hpp"

#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "core/atomic_file.hpp"
#include "eval/plotly_bundle.hpp"

namespace glmbslam::eval {
namespace {

// Runs before the plotly bundle: records script errors, rejected promises and console.error calls so a
// broken page says so (in the page and in <body data-errors>).
constexpr const char* kErrorCapture = R"js(
window.reportErrors = [];
window.addEventListener('error', function (e) { window.reportErrors.push(String(e.message || e)); });
window.addEventListener('unhandledrejection', function (e) { window.reportErrors.push(String(e.reason)); });
(function () {
  var original = console.error;
  console.error = function () {
    window.reportErrors.push(Array.prototype.map.call(arguments, String).join(' '));
    original.apply(console, arguments);
  };
})();
)js";

// Builds the page from the JSON in #report-data and draws the plots.
constexpr const char* kPageScript = R"js(
(function () {
  var report = JSON.parse(document.getElementById('report-data').textContent);
  var body = document.body;
  function el(tag, cls, text) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }
  var main = document.getElementById('report');
  var toc = document.getElementById('toc');
  main.appendChild(el('h1', '', report.title));
  if (report.subtitle) main.appendChild(el('p', 'subtitle', report.subtitle));
  var jobs = [], expected = 0, sections = 0;
  report.blocks.forEach(function (b) {
    if (b.kind === 'section') {
      var h = el('h2', '', b.heading);
      h.id = 'section-' + (++sections);
      main.appendChild(h);
      var link = el('a', '', b.heading);
      link.href = '#' + h.id;
      toc.appendChild(link);
      if (b.note) main.appendChild(el('p', 'note', b.note));
    } else if (b.kind === 'plot') {
      var div = el('div', 'plot');
      div.style.height = b.height + 'px';
      main.appendChild(div);
      var layout = Object.assign({ margin: { l: 60, r: 20, t: 50, b: 50 }, hovermode: 'closest' }, b.layout);
      layout.title = { text: b.title };
      expected += b.data.length;
      jobs.push(Plotly.newPlot(div, b.data, layout, { responsive: true, displaylogo: false }));
    } else if (b.kind === 'table') {
      var wrap = el('div', 'table');
      var table = el('table');
      if (b.caption) table.appendChild(el('caption', '', b.caption));
      var head = el('tr');
      b.header.forEach(function (c) { head.appendChild(el('th', '', c)); });
      table.appendChild(el('thead')).appendChild(head);
      var tbody = table.appendChild(el('tbody'));
      b.rows.forEach(function (r) {
        var tr = tbody.appendChild(el('tr'));
        r.forEach(function (c) { tr.appendChild(el('td', '', c)); });
      });
      wrap.appendChild(table);
      main.appendChild(wrap);
    } else if (b.kind === 'text') {
      var details = el('details');
      details.open = !b.collapsed;
      details.appendChild(el('summary', '', b.caption));
      details.appendChild(el('pre', '', b.text));
      main.appendChild(details);
    }
  });
  // Traces actually drawn: SVG trace groups of 2D plots, WebGL objects of 3D scenes.
  function drawn(gd) {
    var n = gd.querySelectorAll('.scatterlayer .trace').length;
    var scene = gd._fullLayout && gd._fullLayout.scene && gd._fullLayout.scene._scene;
    if (scene && scene.glplot) n += Object.keys(scene.traces).length;
    return n;
  }
  function done(status, traces) {
    body.dataset.plots = String(jobs.length);
    body.dataset.expectedTraces = String(expected);
    body.dataset.traces = String(traces);
    body.dataset.errors = String(window.reportErrors.length);
    if (window.reportErrors.length) {
      var box = el('pre', 'errors', 'Errors while drawing this report:\n' + window.reportErrors.join('\n'));
      main.insertBefore(box, main.firstChild);
    }
    body.dataset.status = status;
  }
  Promise.all(jobs).then(function (gds) {
    var traces = 0;
    gds.forEach(function (gd) {
      var n = drawn(gd);
      gd.dataset.traces = String(n);
      traces += n;
    });
    done('ready', traces);
  }, function (e) {
    console.error('report: ' + e);
    done('failed', 0);
  });
})();
)js";

constexpr const char* kStyle = R"css(
body { font-family: system-ui, sans-serif; margin: 0; color: #222; background: #fafafa; }
nav#toc { position: sticky; top: 0; background: #fff; border-bottom: 1px solid #ddd; padding: 6px 16px;
  z-index: 10; font-size: 14px; }
nav#toc a { margin-right: 14px; color: #1f77b4; text-decoration: none; }
main#report { max-width: 1200px; margin: 0 auto; padding: 8px 16px 40px; }
h1 { font-size: 24px; margin: 16px 0 4px; }
h2 { font-size: 19px; margin: 28px 0 6px; border-bottom: 1px solid #ddd; padding-bottom: 4px; }
p.subtitle { color: #555; margin-top: 0; }
p.note { color: #555; font-size: 14px; margin: 4px 0 8px; }
div.plot { background: #fff; border: 1px solid #e4e4e4; margin: 10px 0; }
div.table { overflow-x: auto; margin: 10px 0; }
table { border-collapse: collapse; background: #fff; font-size: 14px; }
caption { text-align: left; font-weight: 600; padding: 4px 0; }
th, td { border: 1px solid #ddd; padding: 3px 10px; text-align: right; white-space: nowrap; }
th:first-child, td:first-child { text-align: left; }
th { background: #f0f0f0; }
details { margin: 10px 0; background: #fff; border: 1px solid #e4e4e4; padding: 6px 10px; }
summary { font-weight: 600; cursor: pointer; }
pre { font-size: 13px; overflow-x: auto; }
pre.errors { color: #b00; background: #fee; border: 1px solid #b00; padding: 8px; }
)css";

std::string escape_html(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

std::string escape_json_for_script(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (char c : json) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

HtmlReport::HtmlReport(std::string title, std::string subtitle)
    : title_(std::move(title)), subtitle_(std::move(subtitle)) {}

void HtmlReport::add_section(const std::string& heading, const std::string& note) {
  blocks_.push_back({{"kind", "section"}, {"heading", heading}, {"note", note}});
}

void HtmlReport::add_plot(const std::string& title, nlohmann::json traces, nlohmann::json layout,
                          int height_px) {
  if (!traces.is_array()) throw std::invalid_argument("HtmlReport::add_plot: traces must be a JSON array");
  if (!layout.is_object()) throw std::invalid_argument("HtmlReport::add_plot: layout must be a JSON object");
  traces_ += traces.size();
  ++plots_;
  blocks_.push_back({{"kind", "plot"},
                     {"title", title},
                     {"data", std::move(traces)},
                     {"layout", std::move(layout)},
                     {"height", height_px}});
}

void HtmlReport::add_table(const std::string& caption, std::vector<std::string> header,
                           std::vector<std::vector<std::string>> rows) {
  for (const auto& r : rows) {
    if (r.size() != header.size())
      throw std::invalid_argument("HtmlReport::add_table: a row of '" + caption + "' has " +
                                  std::to_string(r.size()) + " cells, the header " +
                                  std::to_string(header.size()));
  }
  blocks_.push_back({{"kind", "table"}, {"caption", caption}, {"header", header}, {"rows", rows}});
}

void HtmlReport::add_text(const std::string& caption, const std::string& text, bool collapsed) {
  blocks_.push_back({{"kind", "text"}, {"caption", caption}, {"text", text}, {"collapsed", collapsed}});
}

void HtmlReport::write_page(std::ostream& out) const {
  // The data object {"blocks": …, "subtitle": …, "title": …} (nlohmann's key order) is written in two parts
  // so that the blocks, the bulk of a long run's report, are dumped once and never copied. Non-finite numbers
  // become null (plotly leaves a gap); invalid UTF-8 is replaced, never an exception.
  const auto dump = [](const nlohmann::json& j) {
    return escape_json_for_script(j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  };
  const std::string head = dump({{"title", title_}, {"subtitle", subtitle_}});  // {"subtitle":…,"title":…}
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      << "<meta name=\"generator\" content=\"glmbslam, plotly.js " << plotly_bundle_version()
      << " (MIT licence, Plotly, Inc.)\">\n"
      << "<title>" << escape_html(title_) << "</title>\n<style>" << kStyle << "</style>\n"
      << "<script>" << kErrorCapture << "</script>\n<script>\n"
      << plotly_bundle()
      << "\n</script>\n</head>\n<body>\n<nav id=\"toc\"></nav>\n<main id=\"report\"></main>\n"
      << "<script id=\"report-data\" type=\"application/json\">{\"blocks\":" << dump(blocks_) << ','
      << std::string_view(head).substr(1) << "</script>\n"
      << "<script>" << kPageScript << "</script>\n</body>\n</html>\n";
}

std::string HtmlReport::html() const {
  std::ostringstream page;
  write_page(page);
  return page.str();
}

void HtmlReport::write(const std::string& path) const {
  write_text_file_atomically(std::filesystem::path(path), [&](std::ostream& out) { write_page(out); });
}

}  // namespace glmbslam::eval
