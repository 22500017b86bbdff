#pragma once
// A small 2D line/scatter plot drawn with OpenCV and saved as PNG: axes with "nice" ticks, tick labels, axis
// labels, a title and a legend. Reusable by `eval`, `run` and `sim`. OpenCV stays out of this header.
#include <cstdint>
#include <string>
#include <vector>

namespace glmbslam::eval {

/// An sRGB colour.
struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

/// A few distinguishable colours (Tableau 10).
namespace colours {
inline constexpr Rgb kBlack{0, 0, 0};
inline constexpr Rgb kBlue{31, 119, 180};
inline constexpr Rgb kOrange{255, 127, 14};
inline constexpr Rgb kGreen{44, 160, 44};
inline constexpr Rgb kRed{214, 39, 40};
inline constexpr Rgb kPurple{148, 103, 189};
inline constexpr Rgb kGrey{127, 127, 127};
}  // namespace colours

enum class SeriesStyle { kLine, kMarkers, kLineMarkers };

class LinePlot {
 public:
  LinePlot(std::string title, std::string x_label, std::string y_label);

  /// Adds a series; x and y must have the same size (std::invalid_argument otherwise). Non-finite points are
  /// skipped (and break a line). An empty label keeps the series out of the legend.
  void add_series(std::vector<double> x, std::vector<double> y, Rgb colour, std::string label,
                  SeriesStyle style = SeriesStyle::kLine, int thickness = 2);

  /// Same scale on both axes (for top views of trajectories).
  void set_equal_aspect(bool equal) { equal_aspect_ = equal; }
  /// Fixes an axis range instead of fitting the data (lo < hi).
  void set_x_range(double lo, double hi);
  void set_y_range(double lo, double hi);
  /// Forces 0 into the y range (for error plots).
  void set_include_zero_y(bool include) { include_zero_y_ = include; }

  /// Renders to PNG at `path` (written atomically); throws InputError naming the file if it cannot be
  /// written.
  void save_png(const std::string& path, int width = 1000, int height = 750) const;

  /// Renders to an encoded PNG byte buffer (for tests and embedding).
  std::vector<std::uint8_t> render_png(int width = 1000, int height = 750) const;

 private:
  struct Series {
    std::vector<double> x, y;
    Rgb colour;
    std::string label;
    SeriesStyle style;
    int thickness;
  };
  std::string title_, x_label_, y_label_;
  std::vector<Series> series_;
  bool equal_aspect_ = false;
  bool include_zero_y_ = false;
  bool fixed_x_ = false, fixed_y_ = false;
  double x_lo_ = 0, x_hi_ = 1, y_lo_ = 0, y_hi_ = 1;
};

/// "Nice" tick positions (steps of 1, 2 or 5 × 10^k) covering [lo, hi], about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

}  // namespace glmbslam::eval
