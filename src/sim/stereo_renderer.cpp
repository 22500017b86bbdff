#include "sim/stereo_renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.hpp"
#include "core/random.hpp"
#include "sim/render_texture.hpp"

namespace glmbslam::sim {
namespace {

constexpr std::size_t kNoiseTableSize = 1U << 16;

struct Vertex {
  double x, y, z;
};

/// Sutherland–Hodgman clip of a convex polygon to z ≥ near. Returns the new vertex count.
int clip_near(const std::array<Vertex, 4>& in, int n, double near, std::array<Vertex, 8>& out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vertex& p = in[static_cast<std::size_t>(i)];
    const Vertex& q = in[static_cast<std::size_t>((i + 1) % n)];
    const bool p_in = p.z >= near;
    const bool q_in = q.z >= near;
    if (p_in) out[static_cast<std::size_t>(m++)] = p;
    if (p_in != q_in) {
      const double t = (near - p.z) / (q.z - p.z);
      out[static_cast<std::size_t>(m++)] = {p.x + t * (q.x - p.x), p.y + t * (q.y - p.y), near};
    }
  }
  return m;
}

}  // namespace

StereoRenderer::StereoRenderer(const StereoWorld& world, const StereoCalibration& calibration,
                               RenderOptions options)
    : world_(world), calib_(calibration), options_(options) {
  if (!(calib_.fx > 0.0) || !(calib_.fy > 0.0) || !(calib_.baseline > 0.0) || calib_.width <= 0 ||
      calib_.height <= 0) {
    throw ConfigError("renderer: calibration needs positive fx, fy, baseline and image size");
  }
  const std::size_t n = static_cast<std::size_t>(calib_.width) * static_cast<std::size_t>(calib_.height);
  inv_depth_.resize(n);
  surface_id_.resize(n);
  noise_table_.resize(kNoiseTableSize);
  RandomStream rng(options_.seed, 0x6e6f697365ULL);  // "noise"
  for (float& v : noise_table_) v = static_cast<float>(rng.normal());
}

void StereoRenderer::render(const Pose3& T_world_left, double time, std::uint64_t frame_id,
                            RenderedFrame& out, bool with_depth) {
  world_.collect(T_world_left.translation(), time, surfaces_);
  render_camera(T_world_left, surfaces_, frame_id, 0, out.left, with_depth ? &out.depth : nullptr);
  Pose3 T_world_right = T_world_left;
  T_world_right.translation() += T_world_left.linear() * Eigen::Vector3d(calib_.baseline, 0.0, 0.0);
  render_camera(T_world_right, surfaces_, frame_id, 1, out.right, nullptr);
}

void StereoRenderer::render_camera(const Pose3& T_world_cam, const SurfaceList& surfaces,
                                   std::uint64_t frame_id, int camera, cv::Mat& image, cv::Mat* depth) {
  rasterise(T_world_cam.inverse(), surfaces);
  shade(T_world_cam, frame_id, camera, image, depth);
}

void StereoRenderer::rasterise(const Pose3& T_cam_world, const SurfaceList& surfaces) {
  const int W = calib_.width;
  const int H = calib_.height;
  const double fx = calib_.fx, fy = calib_.fy, cx = calib_.cx, cy = calib_.cy;
  const double near = options_.near_plane;
  std::fill(inv_depth_.begin(), inv_depth_.end(), 0.0f);
  std::fill(surface_id_.begin(), surface_id_.end(), -1);
  prepared_.clear();
  const Eigen::Matrix3d R = T_cam_world.linear();
  const Eigen::Vector3d t = T_cam_world.translation();
  // Frustum half-spaces through the camera centre (outside when the expression is positive), one pixel
  // margin.
  const double xl = cx + 1.0, xr = W - cx + 1.0, yt = cy + 1.0, yb = H - cy + 1.0;

  std::array<Vertex, 4> cam;
  std::array<Vertex, 8> poly;
  for (const Surface& s : surfaces) {
    const int n = s.corner_count;
    unsigned all_out = 0x1F;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d p = R * s.corners[static_cast<std::size_t>(i)] + t;
      cam[static_cast<std::size_t>(i)] = {p.x(), p.y(), p.z()};
      unsigned out = 0;
      if (p.z() < near) out |= 1U;
      if (-fx * p.x() - xl * p.z() > 0.0) out |= 2U;
      if (fx * p.x() - xr * p.z() > 0.0) out |= 4U;
      if (-fy * p.y() - yt * p.z() > 0.0) out |= 8U;
      if (fy * p.y() - yb * p.z() > 0.0) out |= 16U;
      all_out &= out;
    }
    if (all_out != 0) continue;
    const Eigen::Vector3d nc = R * s.normal;
    const Eigen::Vector3d oc = R * s.origin + t;
    const double d = nc.dot(R * s.corners[0] + t);  // plane nc·X = d
    if (std::abs(d) < 1e-9) continue;               // seen edge-on
    if (!s.two_sided && d >= 0.0) continue;         // seen from behind
    const int m = clip_near(cam, n, near, poly);
    if (m < 3) continue;

    Prepared p;
    p.surface = &s;
    p.A = nc.x() / (fx * d);
    p.B = nc.y() / (fy * d);
    p.C = (nc.z() - nc.x() * cx / fx - nc.y() * cy / fy) / d;
    const Eigen::Vector3d eu = R * s.axis_u;
    const Eigen::Vector3d ev = R * s.axis_v;
    const double ku = oc.dot(eu);
    const double kv = oc.dot(ev);
    p.Au = eu.x() / fx - ku * p.A;
    p.Bu = eu.y() / fy - ku * p.B;
    p.Cu = (eu.z() - eu.x() * cx / fx - eu.y() * cy / fy) - ku * p.C;
    p.Av = ev.x() / fx - kv * p.A;
    p.Bv = ev.y() / fy - kv * p.B;
    p.Cv = (ev.z() - ev.x() * cx / fx - ev.y() * cy / fy) - kv * p.C;
    p.nx = nc.x();
    p.ny = nc.y();
    p.nz = nc.z();
    const auto id = static_cast<std::int32_t>(prepared_.size());
    prepared_.push_back(p);

    // Project and scan-convert.
    std::array<double, 8> pu, pv;
    double vmin = 1e300, vmax = -1e300;
    for (int i = 0; i < m; ++i) {
      const Vertex& q = poly[static_cast<std::size_t>(i)];
      pu[static_cast<std::size_t>(i)] = fx * q.x / q.z + cx;
      pv[static_cast<std::size_t>(i)] = fy * q.y / q.z + cy;
      vmin = std::min(vmin, pv[static_cast<std::size_t>(i)]);
      vmax = std::max(vmax, pv[static_cast<std::size_t>(i)]);
    }
    constexpr double kEps = 1e-3;  // closes cracks between surfaces sharing an edge
    const int row0 = std::max(0, static_cast<int>(std::ceil(vmin - kEps)));
    const int row1 = std::min(H - 1, static_cast<int>(std::floor(vmax + kEps)));
    for (int row = row0; row <= row1; ++row) {
      const double y = row;
      double xmin = 1e300, xmax = -1e300;
      for (int i = 0; i < m; ++i) {
        const std::size_t a = static_cast<std::size_t>(i);
        const std::size_t b = static_cast<std::size_t>((i + 1) % m);
        const double ya = pv[a], yb2 = pv[b];
        if ((ya - kEps > y && yb2 - kEps > y) || (ya + kEps < y && yb2 + kEps < y)) continue;
        if (std::abs(yb2 - ya) < 1e-12) {
          xmin = std::min(xmin, std::min(pu[a], pu[b]));
          xmax = std::max(xmax, std::max(pu[a], pu[b]));
        } else {
          const double tt = std::clamp((y - ya) / (yb2 - ya), 0.0, 1.0);
          const double x = pu[a] + tt * (pu[b] - pu[a]);
          xmin = std::min(xmin, x);
          xmax = std::max(xmax, x);
        }
      }
      if (xmin > xmax) continue;
      const int col0 = std::max(0, static_cast<int>(std::ceil(std::max(xmin - kEps, -1.0))));
      const int col1 =
          std::min(W - 1, static_cast<int>(std::floor(std::min(xmax + kEps, static_cast<double>(W)))));
      if (col0 > col1) continue;
      const std::size_t base = static_cast<std::size_t>(row) * static_cast<std::size_t>(W);
      double w = p.A * col0 + p.B * y + p.C;
      for (int col = col0; col <= col1; ++col, w += p.A) {
        const float wf = static_cast<float>(w);
        const std::size_t k = base + static_cast<std::size_t>(col);
        if (wf > inv_depth_[k]) {
          inv_depth_[k] = wf;
          surface_id_[k] = id;
        }
      }
    }
  }
}

void StereoRenderer::shade(const Pose3& T_world_cam, std::uint64_t frame_id, int camera, cv::Mat& image,
                           cv::Mat* depth) {
  const int W = calib_.width;
  const int H = calib_.height;
  const double fx = calib_.fx, fy = calib_.fy, cx = calib_.cx, cy = calib_.cy;
  image.create(H, W, CV_8UC1);
  if (depth != nullptr) depth->create(H, W, CV_32FC1);
  const PhotometricOptions& ph = options_.photometric;

  // Per-frame, per-camera exposure and the noise stream.
  RandomStream rng(options_.seed, frame_id * 2 + static_cast<std::uint64_t>(camera));
  const double gain = ph.exposure_sigma > 0.0 ? std::exp(ph.exposure_sigma * rng.normal()) : 1.0;
  std::uint32_t noise_state = static_cast<std::uint32_t>(rng.engine()()) | 1U;
  const bool noisy = ph.noise_sigma > 0.0;
  const float noise_sigma = static_cast<float>(ph.noise_sigma);

  // Sky: brighter towards the zenith (few features).
  const Eigen::Vector3d up_cam = T_world_cam.linear().transpose() * world_.up();
  const double r_corner2 = std::max(cx * cx, (W - cx) * (W - cx)) + std::max(cy * cy, (H - cy) * (H - cy));
  const double vig = ph.vignetting / r_corner2;
  const auto inv_fx = static_cast<float>(1.0 / fx);

  for (int row = 0; row < H; ++row) {
    auto* img = image.ptr<std::uint8_t>(row);
    float* dep = depth != nullptr ? depth->ptr<float>(row) : nullptr;
    const double ry = (row - cy) / fy;
    const std::size_t base = static_cast<std::size_t>(row) * static_cast<std::size_t>(W);
    for (int col = 0; col < W; ++col) {
      const std::size_t k = base + static_cast<std::size_t>(col);
      const std::int32_t id = surface_id_[k];
      const double rx = (col - cx) / fx;
      const double r2 = rx * rx + ry * ry + 1.0;
      double value;
      if (id < 0) {
        const double elev = (rx * up_cam.x() + ry * up_cam.y() + up_cam.z()) / std::sqrt(r2);
        value = 0.80 + 0.12 * std::clamp(elev * 2.5, -0.5, 1.0);
        if (dep != nullptr) dep[col] = 0.0f;
      } else {
        const Prepared& p = prepared_[static_cast<std::size_t>(id)];
        const double w = p.A * col + p.B * row + p.C;
        const double z = 1.0 / w;
        const double a = (p.Au * col + p.Bu * row + p.Cu) * z;
        const double b = (p.Av * col + p.Bv * row + p.Cv) * z;
        // Footprint: z·|r|/fx across the ray, divided by √cosθ (geometric mean of the two axes on the
        // surface).
        const float rn = std::sqrt(static_cast<float>(r2));
        const float cos_t = std::max(std::abs(static_cast<float>(p.nx * rx + p.ny * ry + p.nz)) / rn, 1e-3f);
        const float fp = static_cast<float>(z) * rn * inv_fx / std::sqrt(cos_t);
        value = texture::albedo(*p.surface, static_cast<float>(a), static_cast<float>(b), fp);
        if (dep != nullptr) dep[col] = static_cast<float>(z);
      }
      const double dx = col - cx, dy = row - cy;
      float out = static_cast<float>(255.0 * gain * value * (1.0 - vig * (dx * dx + dy * dy)));
      if (noisy) {
        noise_state ^= noise_state << 13;
        noise_state ^= noise_state >> 17;
        noise_state ^= noise_state << 5;
        out += noise_sigma * noise_table_[noise_state >> 16];
      }
      img[col] = static_cast<std::uint8_t>(std::clamp(out, 0.0f, 255.0f) + 0.5f);
    }
  }
}

}  // namespace glmbslam::sim
