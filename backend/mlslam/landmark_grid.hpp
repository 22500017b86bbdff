#pragma once
// A voxel hash of landmark positions for the E-step's candidate search: the landmarks a pose may see lie
// within the detection model's query radius of the camera, so only the cells of that ball's bounding cube are
// visited instead of the whole map (each E-step would otherwise test every landmark against every pose).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::backend {

/// Landmark indices hashed by the cell of their position (D = 2 or 3 dimensions).
template <int D>
class LandmarkGrid {
 public:
  using Point = Eigen::Matrix<double, D, 1>;

  /// Cells of `cell` metres; position_of(j) is landmark j's position (non-finite positions are left out).
  template <class PositionOf>
  LandmarkGrid(std::size_t count, PositionOf&& position_of, double cell) : cell_(cell) {
    cells_.reserve(count / 4 + 1);
    for (std::size_t j = 0; j < count; ++j) {
      const Point q = position_of(j);
      if (!q.allFinite()) continue;
      cells_[key(coords(q))].push_back(static_cast<int>(j));
    }
  }

  /// Indices of the landmarks whose cell meets the cube of half-width `radius` around `centre`, ascending
  /// (a superset of those within `radius`).
  std::vector<int> near(const Point& centre, double radius) const {
    return in_box(centre - Point::Constant(radius), centre + Point::Constant(radius));
  }

  /// near() less the landmarks j with keep(j) false.
  template <class Keep>
  std::vector<int> near_if(const Point& centre, double radius, Keep&& keep) const {
    return in_box_if(centre - Point::Constant(radius), centre + Point::Constant(radius), keep);
  }

  /// Indices of the landmarks whose cell meets the axis-aligned box [lo, hi], ascending (a superset of those
  /// inside it).
  std::vector<int> in_box(const Point& lo_corner, const Point& hi_corner) const {
    return in_box_if(lo_corner, hi_corner, [](int) { return true; });
  }

  /// in_box() less the landmarks j with keep(j) false (tested before the sort, which then has fewer to
  /// order).
  template <class Keep>
  std::vector<int> in_box_if(const Point& lo_corner, const Point& hi_corner, Keep&& keep) const {
    std::vector<int> out;
    const Eigen::Matrix<long long, D, 1> lo = coords(lo_corner);
    const Eigen::Matrix<long long, D, 1> hi = coords(hi_corner);
    Eigen::Matrix<long long, D, 1> c = lo;
    while (true) {
      const auto it = cells_.find(key(c));
      if (it != cells_.end())
        for (int j : it->second)
          if (keep(j)) out.push_back(j);
      int d = 0;
      for (; d < D; ++d) {
        if (c(d) < hi(d)) {
          ++c(d);
          break;
        }
        c(d) = lo(d);
      }
      if (d == D) break;
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());  // two cells may share a hash key
    return out;
  }

 private:
  Eigen::Matrix<long long, D, 1> coords(const Point& q) const {
    Eigen::Matrix<long long, D, 1> c;
    for (int d = 0; d < D; ++d) c(d) = static_cast<long long>(std::floor(q(d) / cell_));
    return c;
  }
  static std::uint64_t key(const Eigen::Matrix<long long, D, 1>& c) {
    std::uint64_t h = 0;
    for (int d = 0; d < D; ++d) h = h * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(c(d) & 0x1FFFFF);
    return h;
  }

  double cell_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

}  // namespace glmbslam::backend
