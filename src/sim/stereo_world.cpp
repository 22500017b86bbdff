#include "sim/stereo_world.hpp"

namespace glmbslam::sim {

Surface make_quad(const Eigen::Vector3d& c0, const Eigen::Vector3d& c1, const Eigen::Vector3d& c2,
                  const Eigen::Vector3d& c3, TextureKind kind, std::uint32_t seed, float albedo,
                  float contrast) {
  Surface s;
  s.corners = {c0, c1, c2, c3};
  s.corner_count = 4;
  s.origin = c0;
  s.axis_u = (c1 - c0).normalized();
  Eigen::Vector3d v = c3 - c0;
  v -= v.dot(s.axis_u) * s.axis_u;
  s.axis_v = v.normalized();
  s.normal = s.axis_u.cross(s.axis_v).normalized();
  s.two_sided = true;
  s.kind = kind;
  s.seed = seed;
  s.albedo = albedo;
  s.contrast = contrast;
  return s;
}

void append_box(const Eigen::Vector3d& bottom_centre, const Eigen::Vector3d& forward,
                const Eigen::Vector3d& up, double length, double width, double height, TextureKind kind,
                std::uint32_t seed, float albedo, float contrast, float param0, float param1,
                SurfaceList& out) {
  const Eigen::Vector3d f = forward.normalized() * (0.5 * length);
  const Eigen::Vector3d side = up.cross(forward).normalized() * (0.5 * width);
  const Eigen::Vector3d h = up * height;
  const Eigen::Vector3d centre = bottom_centre + 0.5 * h;
  // Bottom corners counter-clockwise seen from above.
  const std::array<Eigen::Vector3d, 4> b = {bottom_centre - f - side, bottom_centre + f - side,
                                            bottom_centre + f + side, bottom_centre - f + side};
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d& p = b[static_cast<std::size_t>(i)];
    const Eigen::Vector3d& q = b[static_cast<std::size_t>((i + 1) % 4)];
    Surface s =
        make_quad(p, q, q + h, p + h, kind, seed * 7u + static_cast<std::uint32_t>(i), albedo, contrast);
    const Eigen::Vector3d mid = 0.5 * (p + q) + 0.5 * h;
    if (s.normal.dot(mid - centre) < 0.0) s.normal = -s.normal;
    s.two_sided = false;
    s.param0 = param0;
    s.param1 = param1;
    out.push_back(s);
  }
  Surface top = make_quad(b[0] + h, b[1] + h, b[2] + h, b[3] + h, kind, seed * 7u + 5u, albedo, contrast);
  if (top.normal.dot(up) < 0.0) top.normal = -top.normal;
  top.two_sided = false;
  top.param0 = param0;
  top.param1 = param1;
  out.push_back(top);
}

}  // namespace glmbslam::sim
