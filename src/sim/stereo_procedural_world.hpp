#pragma once
// A street world generated procedurally and deterministically around a trajectory (KITTI camera frames:
// x right, y down, z forward; the world's vertical is its y axis).
//
// The trajectory is resampled every 2 m of horizontal arc length into "stations". Everything is a pure
// function of (seed, trajectory), generated lazily for the surroundings of each camera position, so the
// memory used per frame does not grow with the sequence length (only the station list, 2 numbers per metre of
// path, is kept):
// - ground: 16 m tiles (two triangles each) whose corner heights follow the trajectory (camera height below
//   the nearby stations, smoothly interpolated, so slopes are followed);
// - at each station and side, with fixed probabilities: a building (façade with windows) 5–14 m from the
// path,
//   a wall/box, a parked car, a pole or a tree; nothing is placed within 3 m of any station (the road
//   corridor stays free) and stations that revisit an already populated place spawn nothing new (loops look
//   the same);
// - far towers on a 100 m grid, at least 60 m from the path (little parallax);
// - optional movers: boxes driving along the road next to the camera's lane (time dependent).
// For speed the constructor also evaluates, once, the objects of every station and the far tower of every
// 100 m cell near the path (pure functions of the station or cell; about 1 kB per station of path), when the
// path is not longer than kMaxCachedStations stations or its box not larger than kMaxTowerCells tower cells;
// beyond that they are generated per frame as above. Either way the surfaces and their order are the same.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/types.hpp"
#include "sim/stereo_world.hpp"

namespace glmbslam::sim {

struct ProceduralWorldOptions {
  std::uint64_t seed = 1;
  double camera_height = 1.65;   ///< metres above the ground
  double frame_interval = 0.1;   ///< seconds between consecutive trajectory poses (movers' timing)
  int movers = 0;                ///< number of moving boxes
  double object_radius = 120.0;  ///< stations farther than this from the camera contribute no objects
  double ground_radius = 200.0;  ///< ground tiles drawn within this square half-size
  double far_radius = 700.0;     ///< far towers drawn within this distance
  bool precompute = true;        ///< false: no station grid array or object caches (same surfaces, slower)
};

/// A resampled point of the trajectory.
struct Station {
  double x = 0.0, y = 0.0, z = 0.0;  ///< camera centre
  double ground = 0.0;               ///< world y of the ground below it
  double tx = 0.0, tz = 1.0;         ///< unit horizontal forward direction
  double s = 0.0;                    ///< horizontal arc length from the start
};

class ProceduralWorld : public StereoWorld {
 public:
  /// `trajectory`: T_world_camera per frame (at least one pose). Throws ConfigError on bad options.
  ProceduralWorld(const PoseList& trajectory, ProceduralWorldOptions options);

  void collect(const Eigen::Vector3d& camera_position, double time, SurfaceList& out) const override;

  /// World y of the ground surface model at horizontal position (x, z) (smooth interpolation of the station
  /// ground heights; the rendered ground triangles interpolate it linearly between 16 m tile corners).
  double ground_height(double x, double z) const;

  const std::vector<Station>& stations() const { return stations_; }
  const ProceduralWorldOptions& options() const { return options_; }

  static constexpr double kStationSpacing = 2.0;            ///< metres
  static constexpr double kCellSize = 16.0;                 ///< station grid and ground tile size, metres
  static constexpr double kCorridor = 3.0;                  ///< free half-width around the path, metres
  static constexpr std::size_t kMaxCachedStations = 50000;  ///< longer paths: station objects per frame
  static constexpr std::int64_t kMaxTowerCells = 1 << 18;   ///< larger boxes: far towers per frame
  static constexpr std::int64_t kMaxGridCells = 1 << 22;    ///< larger boxes: station cells in a hash map

 private:
  struct Tower {
    bool present = false;     // a tower stands in the cell (and clear of the path)
    double x = 0.0, z = 0.0;  // its centre
    std::size_t first = 0;    // its surfaces: tower_surfaces_[first, next cell's first)
  };
  void build_station_grid();
  void build_caches();
  /// The far tower of 100 m cell (i, j): appends its faces and sets its centre; false if there is none.
  bool make_tower(std::int64_t i, std::int64_t j, double& x, double& z, SurfaceList& out) const;
  template <typename F>
  void for_each_station_near(double x, double z, double radius, F&& f) const;
  bool is_revisit(std::size_t k) const;
  bool footprint_clear(double cx, double cz, double fx, double fz, double half_length,
                       double half_width) const;
  void append_station_objects(std::size_t k, SurfaceList& out) const;
  void append_far_towers(const Eigen::Vector3d& camera, SurfaceList& out) const;
  void append_ground(const Eigen::Vector3d& camera, SurfaceList& out) const;
  void append_movers(double time, SurfaceList& out) const;
  Station station_at(double s) const;

  ProceduralWorldOptions options_;
  std::vector<Station> stations_;
  std::vector<double> frame_arc_;             // arc length of every trajectory pose
  std::vector<std::size_t> coarse_stations_;  // every 25th station (far-field ground height)
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;  // station cells (large boxes)
  // Station cells as a dense array over the stations' box (dense_): stations of cell c are
  // cell_stations_[cell_start_[c], cell_start_[c + 1]), c = (i − grid_i0_)·grid_nj_ + (j − grid_j0_).
  bool dense_ = false;
  std::int64_t grid_i0_ = 0, grid_j0_ = 0, grid_ni_ = 0, grid_nj_ = 0;
  std::vector<std::uint32_t> cell_start_, cell_stations_;
  // Station objects: station_surfaces_[station_offset_[k], station_offset_[k + 1]) (empty: not cached).
  SurfaceList station_surfaces_;
  std::vector<std::size_t> station_offset_;
  // Far towers per 100 m cell over [tower_i0_, +tower_ni_) × [tower_j0_, +tower_nj_).
  std::int64_t tower_i0_ = 0, tower_j0_ = 0, tower_ni_ = 0, tower_nj_ = 0;
  std::vector<Tower> towers_;
  SurfaceList tower_surfaces_;
};

}  // namespace glmbslam::sim
