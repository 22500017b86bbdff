#pragma once
// The 3D world seen by the synthetic stereo renderer: a set of textured planar convex polygons ("surfaces").
// A world answers one question: which surfaces may be visible from a camera at a given position and time.
// Two worlds: SurfaceListWorld (an explicit list, for tests) and ProceduralWorld
// (stereo_procedural_world.hpp: roads, buildings, poles, trees, far towers and moving boxes generated
// deterministically around a trajectory).
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/types.hpp"

namespace glmbslam::sim {

/// Texture families (render_texture.hpp). All are deterministic functions of the surface point; the rectangle
/// patterns are sampled from one precomputed mip-mapped tile (texture_tile.hpp) at a per-surface offset.
enum class TextureKind : std::uint8_t {
  kConstant,  ///< uniform albedo
  kGround,    ///< asphalt-like: rectangles at several scales (pattern unit 0.9 m, world x/z axes)
  kFacade,    ///< wall with a grid of windows (param0 = cell width, param1 = cell height, metres)
  kMondrian,  ///< overlapping rectangles at several scales (boxes, vehicles)
  kBands,     ///< horizontal bands along v (poles; param0 = period, metres)
  kFoliage,   ///< dense small high-contrast blobs (tree canopies)
  kDisc,      ///< bright disc of radius param0 centred at texture coordinates (0, 0) (test markers)
};

/// A textured planar convex polygon (3 or 4 corners, in order around the polygon) in world coordinates.
/// Texture coordinates of a point X on it: (a, b) = ((X − origin)·axis_u, (X − origin)·axis_v), in metres.
struct Surface {
  std::array<Eigen::Vector3d, 4> corners;
  int corner_count = 4;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();
  /// Unit normal on the visible side; if !two_sided the surface is not drawn when seen from behind.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  bool two_sided = true;
  TextureKind kind = TextureKind::kConstant;
  std::uint32_t seed = 0;  ///< texture seed
  float albedo = 0.5f;     ///< mean reflectance in [0, 1]
  float contrast = 0.3f;   ///< pattern amplitude
  float param0 = 1.0f;
  float param1 = 1.0f;
};

using SurfaceList = std::vector<Surface>;

/// A quad with corners c0, c1, c2, c3 (in order); texture axes u along c1 − c0, v along c3 − c0
/// (made orthogonal to u); normal from u × v unless `outward` is non-zero (then its sign picks the side).
Surface make_quad(const Eigen::Vector3d& c0, const Eigen::Vector3d& c1, const Eigen::Vector3d& c2,
                  const Eigen::Vector3d& c3, TextureKind kind, std::uint32_t seed, float albedo,
                  float contrast);

/// An oriented box: centre of its bottom face, unit horizontal direction `forward` (its length axis), world
/// up vector `up` (unit), length (along forward), width, height. Appends its 5 visible faces (4 sides + top)
/// as one-sided outward quads; texture v axis points up on the sides.
void append_box(const Eigen::Vector3d& bottom_centre, const Eigen::Vector3d& forward,
                const Eigen::Vector3d& up, double length, double width, double height, TextureKind kind,
                std::uint32_t seed, float albedo, float contrast, float param0, float param1,
                SurfaceList& out);

class StereoWorld {
 public:
  virtual ~StereoWorld() = default;
  /// Appends (after clearing `out`) every surface that may be visible from a camera centred at
  /// `camera_position` (world frame) at time `time` (seconds; moving objects depend on it). Thread-safe.
  virtual void collect(const Eigen::Vector3d& camera_position, double time, SurfaceList& out) const = 0;
  /// Unit vector pointing up in the world frame (sky shading). KITTI camera frames: −y.
  virtual Eigen::Vector3d up() const { return -Eigen::Vector3d::UnitY(); }
};

/// A fixed list of surfaces, all returned for every camera position.
class SurfaceListWorld : public StereoWorld {
 public:
  explicit SurfaceListWorld(SurfaceList surfaces) : surfaces_(std::move(surfaces)) {}
  void collect(const Eigen::Vector3d&, double, SurfaceList& out) const override { out = surfaces_; }
  const SurfaceList& surfaces() const { return surfaces_; }

 private:
  SurfaceList surfaces_;
};

}  // namespace glmbslam::sim
