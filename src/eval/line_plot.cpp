#include "eval/line_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace glmbslam::eval {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTickFontScale = 0.5;
constexpr double kLabelFontScale = 0.6;
constexpr double kTitleFontScale = 0.7;

cv::Scalar bgr(Rgb c) {
  return cv::Scalar(c.b, c.g, c.r);
}

std::string tick_label(double v, double step) {
  if (std::abs(v) < 1e-12 * std::max(1.0, step)) v = 0.0;
  char buf[32];
  const double a = std::abs(step);
  if (a >= 1e5 || a < 1e-3) {
    std::snprintf(buf, sizeof(buf), "%.3g", v);
  } else {
    const int decimals = a >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(a) - 1e-9));
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  }
  return buf;
}

void put_text_centered(cv::Mat& img, const std::string& text, cv::Point centre, double scale,
                       int thickness = 1) {
  int base = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, thickness, &base);
  cv::putText(img, text, cv::Point(centre.x - s.width / 2, centre.y + s.height / 2), kFont, scale,
              cv::Scalar(0, 0, 0), thickness, cv::LINE_AA);
}

/// Expands [lo, hi] so it is not degenerate and has a small margin.
void pad_range(double& lo, double& hi) {
  if (!(lo <= hi)) {
    lo = 0.0;
    hi = 1.0;
  }
  if (hi - lo < 1e-12 * std::max(1.0, std::abs(hi))) {
    const double d = std::max(1.0, std::abs(hi)) * 0.5;
    lo -= d;
    hi += d;
    return;
  }
  const double m = 0.04 * (hi - lo);
  lo -= m;
  hi += m;
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || target < 1) return ticks;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double f : {1.0, 2.0, 5.0, 10.0}) {
    step = f * mag;
    if (step >= raw) break;
  }
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (double v = first; v <= hi + 1e-9 * step; v += step) ticks.push_back(v);
  return ticks;
}

LinePlot::LinePlot(std::string title, std::string x_label, std::string y_label)
    : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)) {}

void LinePlot::add_series(std::vector<double> x, std::vector<double> y, Rgb colour, std::string label,
                          SeriesStyle style, int thickness) {
  if (x.size() != y.size()) throw std::invalid_argument("LinePlot::add_series: x and y differ in size");
  series_.push_back(
      Series{std::move(x), std::move(y), colour, std::move(label), style, std::max(1, thickness)});
}

void LinePlot::set_x_range(double lo, double hi) {
  if (!(lo < hi)) throw std::invalid_argument("LinePlot::set_x_range: need lo < hi");
  fixed_x_ = true;
  x_lo_ = lo;
  x_hi_ = hi;
}

void LinePlot::set_y_range(double lo, double hi) {
  if (!(lo < hi)) throw std::invalid_argument("LinePlot::set_y_range: need lo < hi");
  fixed_y_ = true;
  y_lo_ = lo;
  y_hi_ = hi;
}

std::vector<std::uint8_t> LinePlot::render_png(int width, int height) const {
  if (width < 200 || height < 150) throw std::invalid_argument("LinePlot: image too small");
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));

  // Data ranges.
  double xl = std::numeric_limits<double>::infinity(), xh = -xl, yl = xl, yh = -xl;
  for (const auto& s : series_) {
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      xl = std::min(xl, s.x[i]);
      xh = std::max(xh, s.x[i]);
      yl = std::min(yl, s.y[i]);
      yh = std::max(yh, s.y[i]);
    }
  }
  if (include_zero_y_ && yl <= yh) {
    yl = std::min(yl, 0.0);
    yh = std::max(yh, 0.0);
  }
  if (!fixed_x_) pad_range(xl, xh);
  if (!fixed_y_) pad_range(yl, yh);
  if (fixed_x_) {
    xl = x_lo_;
    xh = x_hi_;
  }
  if (fixed_y_) {
    yl = y_lo_;
    yh = y_hi_;
  }
  if (include_zero_y_ && !fixed_y_) {
    // Keep the axis starting at 0 for non-negative data (error plots).
    bool any_negative = false;
    for (const auto& s : series_)
      for (double v : s.y) any_negative = any_negative || (std::isfinite(v) && v < 0.0);
    if (!any_negative) yl = 0.0;
  }

  // Plot area.
  const int left = 90, right = 25, top = 50, bottom = 70;
  cv::Rect area(left, top, width - left - right, height - top - bottom);
  if (equal_aspect_) {
    const double sx = (xh - xl) / area.width;
    const double sy = (yh - yl) / area.height;
    if (sx > sy) {
      const double extra = (sx * area.height - (yh - yl)) / 2.0;
      yl -= extra;
      yh += extra;
    } else {
      const double extra = (sy * area.width - (xh - xl)) / 2.0;
      xl -= extra;
      xh += extra;
    }
  }
  auto to_px = [&](double x, double y) {
    return cv::Point2d(area.x + (x - xl) / (xh - xl) * area.width,
                       area.y + (yh - y) / (yh - yl) * area.height);
  };

  // Grid and ticks.
  const cv::Scalar grid(225, 225, 225), axis(0, 0, 0);
  const std::vector<double> xt = nice_ticks(xl, xh, 8);
  const std::vector<double> yt = nice_ticks(yl, yh, 7);
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1.0;
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (double v : xt) {
    const int px = static_cast<int>(std::lround(to_px(v, yl).x));
    cv::line(img, {px, area.y}, {px, area.y + area.height}, grid, 1);
    cv::line(img, {px, area.y + area.height}, {px, area.y + area.height + 5}, axis, 1);
    put_text_centered(img, tick_label(v, xstep), {px, area.y + area.height + 18}, kTickFontScale);
  }
  for (double v : yt) {
    const int py = static_cast<int>(std::lround(to_px(xl, v).y));
    cv::line(img, {area.x, py}, {area.x + area.width, py}, grid, 1);
    cv::line(img, {area.x - 5, py}, {area.x, py}, axis, 1);
    const std::string t = tick_label(v, ystep);
    int base = 0;
    const cv::Size s = cv::getTextSize(t, kFont, kTickFontScale, 1, &base);
    cv::putText(img, t, {area.x - 8 - s.width, py + s.height / 2}, kFont, kTickFontScale, axis, 1,
                cv::LINE_AA);
  }

  // Series, drawn into the plot area only (sub-image view clips them), with sub-pixel precision.
  cv::Mat roi = img(area);
  constexpr int kShift = 4;
  constexpr double kScale = 1 << kShift;
  auto fixed = [&](double x, double y) {
    const cv::Point2d p = to_px(x, y) - cv::Point2d(area.x, area.y);
    const double lim = 1e5;
    return cv::Point(static_cast<int>(std::lround(std::clamp(p.x, -lim, lim) * kScale)),
                     static_cast<int>(std::lround(std::clamp(p.y, -lim, lim) * kScale)));
  };
  for (const auto& s : series_) {
    const cv::Scalar c = bgr(s.colour);
    if (s.style != SeriesStyle::kMarkers) {
      std::vector<cv::Point> run;
      auto flush = [&] {
        if (run.size() >= 2) cv::polylines(roi, run, false, c, s.thickness, cv::LINE_AA, kShift);
        run.clear();
      };
      for (size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
          flush();
          continue;
        }
        run.push_back(fixed(s.x[i], s.y[i]));
      }
      flush();
    }
    if (s.style != SeriesStyle::kLine) {
      for (size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        cv::circle(roi, fixed(s.x[i], s.y[i]), (s.thickness + 2) * static_cast<int>(kScale), c, cv::FILLED,
                   cv::LINE_AA, kShift);
      }
    }
  }
  cv::rectangle(img, area, axis, 1);

  // Title and axis labels (the y label rotated by 90°).
  put_text_centered(img, title_, {width / 2, top / 2}, kTitleFontScale, 2);
  put_text_centered(img, x_label_, {area.x + area.width / 2, height - 22}, kLabelFontScale);
  if (!y_label_.empty()) {
    int base = 0;
    const cv::Size s = cv::getTextSize(y_label_, kFont, kLabelFontScale, 1, &base);
    cv::Mat label(s.height + base + 6, s.width + 6, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::putText(label, y_label_, {3, s.height + 3}, kFont, kLabelFontScale, axis, 1, cv::LINE_AA);
    cv::Mat rotated;
    cv::rotate(label, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int x0 = 8;
    const int y0 = std::max(0, area.y + area.height / 2 - rotated.rows / 2);
    const int h = std::min(rotated.rows, height - y0);
    const int w = std::min(rotated.cols, left - x0);
    if (h > 0 && w > 0) rotated(cv::Rect(0, 0, w, h)).copyTo(img(cv::Rect(x0, y0, w, h)));
  }

  // Legend (top-left inside the plot area).
  int rows = 0, legend_w = 0;
  for (const auto& s : series_) {
    if (s.label.empty()) continue;
    int base = 0;
    legend_w = std::max(legend_w, cv::getTextSize(s.label, kFont, kTickFontScale, 1, &base).width);
    ++rows;
  }
  if (rows > 0) {
    const int row_h = 22;
    const int bw = legend_w + 60, bh = rows * row_h + 10;
    // Of the four inner corners, put the legend where it hides the fewest data points.
    const cv::Point corners[4] = {{area.x + 10, area.y + 10},
                                  {area.x + area.width - 10 - bw, area.y + 10},
                                  {area.x + 10, area.y + area.height - 10 - bh},
                                  {area.x + area.width - 10 - bw, area.y + area.height - 10 - bh}};
    int best = 0;
    long best_hidden = -1;
    for (int k = 0; k < 4; ++k) {
      const cv::Rect candidate(corners[k].x, corners[k].y, bw, bh);
      long hidden = 0;
      for (const auto& s : series_) {
        for (size_t i = 0; i < s.x.size(); ++i) {
          if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
          const cv::Point2d q = to_px(s.x[i], s.y[i]);
          if (candidate.contains(cv::Point(static_cast<int>(q.x), static_cast<int>(q.y)))) ++hidden;
        }
      }
      if (best_hidden < 0 || hidden < best_hidden) {
        best_hidden = hidden;
        best = k;
      }
    }
    const cv::Rect box(corners[best].x, corners[best].y, bw, bh);
    cv::rectangle(img, box, cv::Scalar(255, 255, 255), cv::FILLED);
    cv::rectangle(img, box, cv::Scalar(160, 160, 160), 1);
    int r = 0;
    for (const auto& s : series_) {
      if (s.label.empty()) continue;
      const int y = box.y + 5 + r * row_h + row_h / 2;
      const cv::Scalar c = bgr(s.colour);
      if (s.style != SeriesStyle::kMarkers)
        cv::line(img, {box.x + 8, y}, {box.x + 40, y}, c, s.thickness, cv::LINE_AA);
      if (s.style != SeriesStyle::kLine)
        cv::circle(img, {box.x + 24, y}, s.thickness + 2, c, cv::FILLED, cv::LINE_AA);
      cv::putText(img, s.label, {box.x + 48, y + 5}, kFont, kTickFontScale, axis, 1, cv::LINE_AA);
      ++r;
    }
  }

  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", img, png)) throw std::runtime_error("LinePlot: PNG encoding failed");
  return png;
}

void LinePlot::save_png(const std::string& path, int width, int height) const {
  const std::vector<std::uint8_t> png = render_png(width, height);
  const auto tmp = temporary_path_for(path);
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError(path, "cannot open for writing");
    out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw InputError(path, "write failed (disk full?)");
    }
  }
  commit_temporary(tmp, path);
}

}  // namespace glmbslam::eval
