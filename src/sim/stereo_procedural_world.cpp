#include "sim/stereo_procedural_world.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/random.hpp"

namespace glmbslam::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBury = 2.0;  // objects extend this far below the ground (no gaps on slopes)
const Eigen::Vector3d kUp(0.0, -1.0, 0.0);

std::uint64_t cell_key(std::int64_t i, std::int64_t j) {
  return (static_cast<std::uint64_t>(i + (1LL << 31)) << 32) | static_cast<std::uint64_t>(j + (1LL << 31));
}

std::int64_t cell_index(double v, double size) {
  return static_cast<std::int64_t>(std::floor(v / size));
}

std::uint32_t draw_seed(RandomStream& rng) {
  return static_cast<std::uint32_t>(rng.engine()() >> 32);
}

// Stream ids of the world's random draws (disjoint ranges).
constexpr std::uint64_t kStationStream = 0;
constexpr std::uint64_t kTowerStream = 1ULL << 60;
constexpr std::uint64_t kMoverStream = 1ULL << 61;
constexpr double kTowerCell = 100.0;  // far tower grid, metres

}  // namespace

ProceduralWorld::ProceduralWorld(const PoseList& trajectory, ProceduralWorldOptions options)
    : options_(options) {
  if (trajectory.empty()) throw ConfigError("procedural world: the trajectory has no poses");
  if (!(options_.camera_height > 0.0) || !(options_.frame_interval > 0.0) || options_.movers < 0 ||
      !(options_.object_radius > 0.0) || !(options_.ground_radius > 0.0) || !(options_.far_radius > 0.0)) {
    throw ConfigError(
        "procedural world: camera height, frame interval and radii must be positive, movers >= 0");
  }
  // Horizontal arc length of every pose.
  frame_arc_.resize(trajectory.size());
  frame_arc_[0] = 0.0;
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const Eigen::Vector3d d = trajectory[i].translation() - trajectory[i - 1].translation();
    frame_arc_[i] = frame_arc_[i - 1] + std::hypot(d.x(), d.z());
  }
  auto forward_of = [&](std::size_t i) {
    const Eigen::Vector3d f = trajectory[i].linear().col(2);
    Eigen::Vector2d h(f.x(), f.z());
    if (h.norm() < 0.1) h = Eigen::Vector2d(0.0, 1.0);
    return Eigen::Vector2d(h.normalized());
  };
  const double total = frame_arc_.back();
  const auto count = static_cast<std::size_t>(std::floor(total / kStationSpacing)) + 1;
  stations_.reserve(count);
  std::size_t seg = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const double s = static_cast<double>(k) * kStationSpacing;
    while (seg + 1 < trajectory.size() && frame_arc_[seg + 1] < s) ++seg;
    Station st;
    Eigen::Vector3d p = trajectory[seg].translation();
    Eigen::Vector2d f = forward_of(seg);
    if (seg + 1 < trajectory.size() && frame_arc_[seg + 1] > frame_arc_[seg]) {
      const double t = std::clamp((s - frame_arc_[seg]) / (frame_arc_[seg + 1] - frame_arc_[seg]), 0.0, 1.0);
      p += t * (trajectory[seg + 1].translation() - p);
      f = ((1.0 - t) * f + t * forward_of(seg + 1));
      if (f.norm() < 1e-6) f = forward_of(seg);
      f.normalize();
    }
    st.x = p.x();
    st.y = p.y();
    st.z = p.z();
    st.ground = p.y() + options_.camera_height;
    st.tx = f.x();
    st.tz = f.y();
    st.s = s;
    stations_.push_back(st);
  }
  for (std::size_t k = 0; k < stations_.size(); ++k) {
    if (k % 25 == 0) coarse_stations_.push_back(k);
  }
  build_station_grid();
  build_caches();
}

void ProceduralWorld::build_station_grid() {
  // Station cells: a dense array of cells over the stations' bounding box when it is small enough (a plain
  // index instead of a hash lookup; cells outside the box are empty), else a hash map. Stations are listed
  // in increasing index within a cell either way, so every query visits them in the same order.
  std::int64_t i_min = INT64_MAX, i_max = INT64_MIN, j_min = INT64_MAX, j_max = INT64_MIN;
  for (const Station& st : stations_) {
    const std::int64_t i = cell_index(st.x, kCellSize), j = cell_index(st.z, kCellSize);
    i_min = std::min(i_min, i);
    i_max = std::max(i_max, i);
    j_min = std::min(j_min, j);
    j_max = std::max(j_max, j);
  }
  const std::int64_t ni = i_max - i_min + 1, nj = j_max - j_min + 1;
  if (!options_.precompute || ni * nj > kMaxGridCells) {
    for (std::size_t k = 0; k < stations_.size(); ++k) {
      grid_[cell_key(cell_index(stations_[k].x, kCellSize), cell_index(stations_[k].z, kCellSize))].push_back(
          static_cast<std::uint32_t>(k));
    }
    return;
  }
  dense_ = true;
  grid_i0_ = i_min;
  grid_j0_ = j_min;
  grid_ni_ = ni;
  grid_nj_ = nj;
  const auto cells = static_cast<std::size_t>(ni * nj);
  std::vector<std::size_t> cell_of(stations_.size());
  cell_start_.assign(cells + 1, 0);
  for (std::size_t k = 0; k < stations_.size(); ++k) {
    const std::int64_t i = cell_index(stations_[k].x, kCellSize) - i_min;
    const std::int64_t j = cell_index(stations_[k].z, kCellSize) - j_min;
    cell_of[k] = static_cast<std::size_t>(i * nj + j);
    ++cell_start_[cell_of[k] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_stations_.resize(stations_.size());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t k = 0; k < stations_.size(); ++k) {
    cell_stations_[fill[cell_of[k]]++] = static_cast<std::uint32_t>(k);
  }
}

void ProceduralWorld::build_caches() {
  // The objects of every station (a pure function of the station) once, instead of once per frame that sees
  // the station, while their memory stays modest (≈1 kB per station).
  if (!options_.precompute) return;
  if (stations_.size() <= kMaxCachedStations) {
    station_offset_.reserve(stations_.size() + 1);
    station_offset_.push_back(0);
    for (std::size_t k = 0; k < stations_.size(); ++k) {
      append_station_objects(k, station_surfaces_);
      station_offset_.push_back(station_surfaces_.size());
    }
  }
  // The far tower of every 100 m cell within far_radius of the stations' bounding box (a pure function of
  // the cell, apart from the distance to the camera, which collect() tests).
  double x_min = 1e300, x_max = -1e300, z_min = 1e300, z_max = -1e300;
  for (const Station& st : stations_) {
    x_min = std::min(x_min, st.x);
    x_max = std::max(x_max, st.x);
    z_min = std::min(z_min, st.z);
    z_max = std::max(z_max, st.z);
  }
  const double r = options_.far_radius;
  const std::int64_t i0 = cell_index(x_min - r, kTowerCell), i1 = cell_index(x_max + r, kTowerCell);
  const std::int64_t j0 = cell_index(z_min - r, kTowerCell), j1 = cell_index(z_max + r, kTowerCell);
  if ((i1 - i0 + 1) * (j1 - j0 + 1) > kMaxTowerCells) return;
  tower_i0_ = i0;
  tower_j0_ = j0;
  tower_ni_ = i1 - i0 + 1;
  tower_nj_ = j1 - j0 + 1;
  towers_.resize(static_cast<std::size_t>(tower_ni_ * tower_nj_));
  for (std::int64_t i = i0; i <= i1; ++i) {
    for (std::int64_t j = j0; j <= j1; ++j) {
      Tower& t = towers_[static_cast<std::size_t>((i - i0) * tower_nj_ + (j - j0))];
      t.first = tower_surfaces_.size();
      t.present = make_tower(i, j, t.x, t.z, tower_surfaces_);
    }
  }
}

template <typename F>
void ProceduralWorld::for_each_station_near(double x, double z, double radius, F&& f) const {
  const std::int64_t i0 = cell_index(x - radius, kCellSize), i1 = cell_index(x + radius, kCellSize);
  const std::int64_t j0 = cell_index(z - radius, kCellSize), j1 = cell_index(z + radius, kCellSize);
  const double r2 = radius * radius;
  if (dense_) {
    // Only the cells inside the stations' box can hold stations; same cell order as below.
    const std::int64_t a0 = std::max(i0, grid_i0_), a1 = std::min(i1, grid_i0_ + grid_ni_ - 1);
    const std::int64_t b0 = std::max(j0, grid_j0_), b1 = std::min(j1, grid_j0_ + grid_nj_ - 1);
    for (std::int64_t i = a0; i <= a1; ++i) {
      for (std::int64_t j = b0; j <= b1; ++j) {
        const auto c = static_cast<std::size_t>((i - grid_i0_) * grid_nj_ + (j - grid_j0_));
        for (std::uint32_t q = cell_start_[c]; q < cell_start_[c + 1]; ++q) {
          const std::uint32_t k = cell_stations_[q];
          const Station& st = stations_[k];
          const double dx = st.x - x, dz = st.z - z;
          const double d2 = dx * dx + dz * dz;
          if (d2 <= r2) f(static_cast<std::size_t>(k), d2);
        }
      }
    }
    return;
  }
  for (std::int64_t i = i0; i <= i1; ++i) {
    for (std::int64_t j = j0; j <= j1; ++j) {
      const auto it = grid_.find(cell_key(i, j));
      if (it == grid_.end()) continue;
      for (std::uint32_t k : it->second) {
        const Station& st = stations_[k];
        const double dx = st.x - x, dz = st.z - z;
        const double d2 = dx * dx + dz * dz;
        if (d2 <= r2) f(static_cast<std::size_t>(k), d2);
      }
    }
  }
}

double ProceduralWorld::ground_height(double x, double z) const {
  // Compactly supported weights (1 − d²/R²)² over nearby stations, blended with an inverse-distance average
  // over every 25th station so that the height is defined (and continuous) everywhere.
  constexpr double kRadius = 40.0;
  double sw = 0.0, sh = 0.0;
  for_each_station_near(x, z, kRadius, [&](std::size_t k, double d2) {
    const double q = 1.0 - d2 / (kRadius * kRadius);
    const double w = q * q;
    sw += w;
    sh += w * stations_[k].ground;
  });
  if (sw > 2.0) return sh / sw;
  double fw = 0.0, fh = 0.0;
  for (std::size_t k : coarse_stations_) {
    const Station& st = stations_[k];
    const double d2 = (st.x - x) * (st.x - x) + (st.z - z) * (st.z - z) + 1.0;
    const double w = 1.0 / (d2 * d2);
    fw += w;
    fh += w * st.ground;
  }
  const double far = fh / fw;
  // Below a total weight of 2 the far-field estimate takes over smoothly.
  const double blend = sw / 2.0;
  return blend * (sh / std::max(sw, 1e-300)) + (1.0 - blend) * far;
}

bool ProceduralWorld::is_revisit(std::size_t k) const {
  constexpr double kRadius = 12.0;
  constexpr double kGap = 60.0;
  const Station& st = stations_[k];
  bool revisit = false;
  for_each_station_near(st.x, st.z, kRadius, [&](std::size_t j, double) {
    if (stations_[j].s < st.s - kGap) revisit = true;
  });
  return revisit;
}

bool ProceduralWorld::footprint_clear(double cx, double cz, double fx, double fz, double half_length,
                                      double half_width) const {
  // Distance from every nearby station to the oriented rectangle must exceed the corridor half-width.
  const double radius = std::hypot(half_length, half_width) + kCorridor;
  bool clear = true;
  for_each_station_near(cx, cz, radius, [&](std::size_t k, double) {
    const Station& st = stations_[k];
    const double dx = st.x - cx, dz = st.z - cz;
    const double along = dx * fx + dz * fz;
    const double across = dx * fz - dz * fx;
    const double ea = std::max(0.0, std::abs(along) - half_length);
    const double ec = std::max(0.0, std::abs(across) - half_width);
    if (ea * ea + ec * ec < kCorridor * kCorridor) clear = false;
  });
  return clear;
}

void ProceduralWorld::append_station_objects(std::size_t k, SurfaceList& out) const {
  if (is_revisit(k)) return;
  const Station& st = stations_[k];
  const double rx = st.tz, rz = -st.tx;  // right of the forward direction (x right, z forward)
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    RandomStream rng(options_.seed,
                     kStationStream + 2 * static_cast<std::uint64_t>(k) + static_cast<unsigned>(side));
    const double u = rng.uniform();
    const double jitter = rng.uniform(-1.0, 1.0);
    const std::uint32_t tex_seed = draw_seed(rng);
    // Object kind by cumulative probability per station and side.
    double length, width, height, lateral;
    TextureKind kind;
    float albedo, contrast, p0 = 1.0f, p1 = 1.0f;
    enum class Kind { kBuilding, kWall, kCar, kPole, kTree } what;
    if (u < 0.10) {
      what = Kind::kBuilding;
      length = rng.uniform(8.0, 24.0);
      width = rng.uniform(6.0, 14.0);
      height = rng.uniform(5.0, 18.0);
      lateral = rng.uniform(5.0, 14.0);
      kind = TextureKind::kFacade;
      albedo = static_cast<float>(rng.uniform(0.35, 0.7));
      contrast = 0.35f;
      p0 = static_cast<float>(rng.uniform(1.8, 3.2));
      p1 = static_cast<float>(rng.uniform(2.6, 3.4));
    } else if (u < 0.16) {
      what = Kind::kWall;
      length = rng.uniform(1.5, 6.0);
      width = rng.uniform(0.8, 3.0);
      height = rng.uniform(0.8, 3.0);
      lateral = rng.uniform(4.0, 9.0);
      kind = TextureKind::kMondrian;
      albedo = static_cast<float>(rng.uniform(0.3, 0.7));
      contrast = 0.45f;
      p0 = static_cast<float>(rng.uniform(0.8, 2.0));
    } else if (u < 0.20) {
      what = Kind::kCar;
      length = rng.uniform(3.8, 4.6);
      width = rng.uniform(1.7, 1.9);
      height = rng.uniform(1.4, 1.6);
      lateral = rng.uniform(3.2, 4.0);
      kind = TextureKind::kMondrian;
      albedo = static_cast<float>(rng.uniform(0.2, 0.8));
      contrast = 0.4f;
      p0 = 1.2f;
    } else if (u < 0.25) {
      what = Kind::kPole;
      length = 0.18;
      width = 0.18;
      height = rng.uniform(4.0, 7.0);
      lateral = rng.uniform(3.3, 6.0);
      kind = TextureKind::kBands;
      albedo = 0.5f;
      contrast = 0.35f;
      p0 = static_cast<float>(rng.uniform(0.25, 0.6));
    } else if (u < 0.31) {
      what = Kind::kTree;
      length = rng.uniform(2.2, 4.0);  // canopy size
      width = length;
      height = rng.uniform(1.9, 3.0);  // trunk height
      lateral = rng.uniform(3.5, 8.0);
      kind = TextureKind::kFoliage;
      albedo = static_cast<float>(rng.uniform(0.22, 0.4));
      contrast = 0.5f;
    } else {
      continue;
    }
    // Centre of the footprint: `lateral` is the distance from the path to the near face.
    const double half_w = 0.5 * width;
    const double off = sign * (lateral + half_w);
    const double cx = st.x + off * rx + jitter * st.tx;
    const double cz = st.z + off * rz + jitter * st.tz;
    if (!footprint_clear(cx, cz, st.tx, st.tz, 0.5 * length, half_w)) continue;
    const Eigen::Vector3d forward(st.tx, 0.0, st.tz);
    const Eigen::Vector3d base(cx, st.ground + kBury, cz);
    if (what == Kind::kTree) {
      append_box(base, forward, kUp, 0.35, 0.35, height + kBury, TextureKind::kBands, tex_seed, 0.3f, 0.2f,
                 0.4f, 1.0f, out);
      append_box(Eigen::Vector3d(cx, st.ground - height, cz), forward, kUp, length, width, length, kind,
                 tex_seed + 1U, albedo, contrast, p0, p1, out);
    } else {
      append_box(base, forward, kUp, length, width, height + kBury, kind, tex_seed, albedo, contrast, p0, p1,
                 out);
    }
  }
}

bool ProceduralWorld::make_tower(std::int64_t i, std::int64_t j, double& x, double& z,
                                 SurfaceList& out) const {
  constexpr double kClearance = 60.0;
  RandomStream rng(options_.seed, kTowerStream + cell_key(i, j) % (1ULL << 59));
  if (rng.uniform() > 0.5) return false;
  x = (static_cast<double>(i) + rng.uniform(0.1, 0.9)) * kTowerCell;
  z = (static_cast<double>(j) + rng.uniform(0.1, 0.9)) * kTowerCell;
  const double size = rng.uniform(12.0, 35.0);
  const double height = rng.uniform(20.0, 80.0);
  const double yaw = rng.uniform(0.0, kPi);
  const float albedo = static_cast<float>(rng.uniform(0.3, 0.65));
  const float cw = static_cast<float>(rng.uniform(2.0, 4.0));
  const float ch = static_cast<float>(rng.uniform(3.0, 4.0));
  const std::uint32_t tex_seed = draw_seed(rng);
  bool near_path = false;
  const double tx = x, tz = z;
  for_each_station_near(tx, tz, kClearance + 0.71 * size, [&](std::size_t, double) { near_path = true; });
  if (near_path) return false;
  const double base_y = ground_height(x, z) + 5.0;
  append_box(Eigen::Vector3d(x, base_y, z), Eigen::Vector3d(std::sin(yaw), 0.0, std::cos(yaw)), kUp, size,
             size, height + 5.0, TextureKind::kFacade, tex_seed, albedo, 0.35f, cw, ch, out);
  return true;
}

void ProceduralWorld::append_far_towers(const Eigen::Vector3d& camera, SurfaceList& out) const {
  const double r = options_.far_radius;
  const std::int64_t i0 = cell_index(camera.x() - r, kTowerCell), i1 = cell_index(camera.x() + r, kTowerCell);
  const std::int64_t j0 = cell_index(camera.z() - r, kTowerCell), j1 = cell_index(camera.z() + r, kTowerCell);
  for (std::int64_t i = i0; i <= i1; ++i) {
    for (std::int64_t j = j0; j <= j1; ++j) {
      const bool cached =
          i >= tower_i0_ && i < tower_i0_ + tower_ni_ && j >= tower_j0_ && j < tower_j0_ + tower_nj_;
      if (cached) {
        const std::size_t c = static_cast<std::size_t>((i - tower_i0_) * tower_nj_ + (j - tower_j0_));
        const Tower& t = towers_[c];
        if (!t.present || std::hypot(t.x - camera.x(), t.z - camera.z()) > r) continue;
        const std::size_t last = c + 1 < towers_.size() ? towers_[c + 1].first : tower_surfaces_.size();
        out.insert(out.end(), tower_surfaces_.begin() + static_cast<std::ptrdiff_t>(t.first),
                   tower_surfaces_.begin() + static_cast<std::ptrdiff_t>(last));
        continue;
      }
      double x = 0.0, z = 0.0;
      const std::size_t before = out.size();
      if (make_tower(i, j, x, z, out) && std::hypot(x - camera.x(), z - camera.z()) > r) {
        out.resize(before);
      }
    }
  }
}

void ProceduralWorld::append_ground(const Eigen::Vector3d& camera, SurfaceList& out) const {
  const double r = options_.ground_radius;
  const std::int64_t i0 = cell_index(camera.x() - r, kCellSize), i1 = cell_index(camera.x() + r, kCellSize);
  const std::int64_t j0 = cell_index(camera.z() - r, kCellSize), j1 = cell_index(camera.z() + r, kCellSize);
  const std::int64_t ni = i1 - i0 + 2, nj = j1 - j0 + 2;
  std::vector<double> h(static_cast<std::size_t>(ni * nj));
  for (std::int64_t a = 0; a < ni; ++a) {
    for (std::int64_t b = 0; b < nj; ++b) {
      h[static_cast<std::size_t>(a * nj + b)] =
          ground_height(static_cast<double>(i0 + a) * kCellSize, static_cast<double>(j0 + b) * kCellSize);
    }
  }
  auto corner = [&](std::int64_t a, std::int64_t b) {
    return Eigen::Vector3d(static_cast<double>(i0 + a) * kCellSize, h[static_cast<std::size_t>(a * nj + b)],
                           static_cast<double>(j0 + b) * kCellSize);
  };
  const auto ground_seed = static_cast<std::uint32_t>(splitmix64(options_.seed ^ 0x67726f756e64ULL));
  for (std::int64_t a = 0; a + 1 < ni; ++a) {
    for (std::int64_t b = 0; b + 1 < nj; ++b) {
      const Eigen::Vector3d c00 = corner(a, b), c10 = corner(a + 1, b), c11 = corner(a + 1, b + 1),
                            c01 = corner(a, b + 1);
      for (int tri = 0; tri < 2; ++tri) {
        Surface s;
        s.corners[0] = c00;
        s.corners[1] = tri == 0 ? c10 : c11;
        s.corners[2] = tri == 0 ? c11 : c01;
        s.corners[3] = s.corners[2];
        s.corner_count = 3;
        s.origin = Eigen::Vector3d::Zero();
        s.axis_u = Eigen::Vector3d::UnitX();
        s.axis_v = Eigen::Vector3d::UnitZ();
        Eigen::Vector3d n = (s.corners[1] - s.corners[0]).cross(s.corners[2] - s.corners[0]).normalized();
        if (n.dot(kUp) < 0.0) n = -n;
        s.normal = n;
        s.two_sided = false;
        s.kind = TextureKind::kGround;
        s.seed = ground_seed;
        s.albedo = 0.38f;
        s.contrast = 0.35f;
        out.push_back(s);
      }
    }
  }
}

Station ProceduralWorld::station_at(double s) const {
  const double q = std::clamp(s / kStationSpacing, 0.0, static_cast<double>(stations_.size() - 1));
  const auto k = static_cast<std::size_t>(std::floor(q));
  if (k + 1 >= stations_.size()) return stations_.back();
  const double t = q - static_cast<double>(k);
  const Station& a = stations_[k];
  const Station& b = stations_[k + 1];
  Station st;
  st.x = a.x + t * (b.x - a.x);
  st.y = a.y + t * (b.y - a.y);
  st.z = a.z + t * (b.z - a.z);
  st.ground = a.ground + t * (b.ground - a.ground);
  Eigen::Vector2d f((1.0 - t) * a.tx + t * b.tx, (1.0 - t) * a.tz + t * b.tz);
  if (f.norm() < 1e-6) f = Eigen::Vector2d(a.tx, a.tz);
  f.normalize();
  st.tx = f.x();
  st.tz = f.y();
  st.s = s;
  return st;
}

void ProceduralWorld::append_movers(double time, SurfaceList& out) const {
  if (options_.movers == 0 || stations_.size() < 2) return;
  // The camera's arc length at `time` (poses are frame_interval apart).
  const double q =
      std::clamp(time / options_.frame_interval, 0.0, static_cast<double>(frame_arc_.size() - 1));
  const auto i = static_cast<std::size_t>(std::floor(q));
  const double s_cam = i + 1 < frame_arc_.size() ? frame_arc_[i] + (q - static_cast<double>(i)) *
                                                                       (frame_arc_[i + 1] - frame_arc_[i])
                                                 : frame_arc_.back();
  for (int m = 0; m < options_.movers; ++m) {
    RandomStream rng(options_.seed, kMoverStream + static_cast<std::uint64_t>(m));
    const double offset = rng.uniform(-20.0, 80.0);
    const double amplitude = rng.uniform(5.0, 25.0);
    const double period = rng.uniform(15.0, 50.0);
    const double phase = rng.uniform(0.0, 2.0 * kPi);
    const double side = rng.uniform() < 0.5 ? -1.0 : 1.0;
    const bool van = rng.uniform() < 0.3;
    const float albedo = static_cast<float>(rng.uniform(0.25, 0.75));
    const std::uint32_t tex_seed = draw_seed(rng);
    const double s = s_cam + offset + amplitude * std::sin(2.0 * kPi * time / period + phase);
    const Station st = station_at(s);
    const double lateral = side * 2.4;
    const double width = van ? 2.2 : 1.8;
    const double x = st.x + lateral * st.tz;
    const double z = st.z - lateral * st.tx;
    append_box(Eigen::Vector3d(x, st.ground + 0.3, z), Eigen::Vector3d(st.tx, 0.0, st.tz), kUp,
               van ? 6.0 : 4.2, width, (van ? 2.6 : 1.5) + 0.3, TextureKind::kMondrian, tex_seed, albedo,
               0.45f, 0.9f, 1.0f, out);
  }
}

void ProceduralWorld::collect(const Eigen::Vector3d& camera_position, double time, SurfaceList& out) const {
  out.clear();
  append_ground(camera_position, out);
  std::vector<std::size_t> near;
  for_each_station_near(camera_position.x(), camera_position.z(), options_.object_radius,
                        [&](std::size_t k, double) { near.push_back(k); });
  std::sort(near.begin(), near.end());  // deterministic surface order
  for (std::size_t k : near) {
    if (station_offset_.empty()) {
      append_station_objects(k, out);
    } else {
      out.insert(out.end(), station_surfaces_.begin() + static_cast<std::ptrdiff_t>(station_offset_[k]),
                 station_surfaces_.begin() + static_cast<std::ptrdiff_t>(station_offset_[k + 1]));
    }
  }
  append_far_towers(camera_position, out);
  append_movers(time, out);
}

}  // namespace glmbslam::sim
