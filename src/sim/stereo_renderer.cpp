#include "sim/stereo_renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/error.hpp"
#include "core/random.hpp"
#include "sim/pixel_noise.hpp"
#include "sim/render_texture.hpp"

namespace glmbslam::sim {
namespace {

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
  const std::size_t band = static_cast<std::size_t>(kBandRows) * static_cast<std::size_t>(calib_.width);
  inv_depth_.resize(band);
  surface_id_.resize(band);
  const double W = calib_.width, H = calib_.height, cx = calib_.cx, cy = calib_.cy;
  const double r_corner2 = std::max(cx * cx, (W - cx) * (W - cx)) + std::max(cy * cy, (H - cy) * (H - cy));
  const double vig = options_.photometric.vignetting / r_corner2;
  const auto w = static_cast<std::size_t>(calib_.width);
  const std::size_t padded = (w + 3) / 4 * 4;
  ray_x_.resize(w);
  vignette_x_.assign(padded, 0.0f);
  row_albedo_.assign(padded, 0.0f);
  for (std::size_t c = 0; c < w; ++c) {
    const double dx = static_cast<double>(c) - cx;
    ray_x_[c] = static_cast<float>(dx / calib_.fx);
    vignette_x_[c] = static_cast<float>(vig * dx * dx);
  }
  ray_norm_.resize(n);
  for (int row = 0; row < calib_.height; ++row) {
    const double ry = (row - cy) / calib_.fy;
    for (std::size_t c = 0; c < w; ++c) {
      const double rx = ray_x_[c];
      ray_norm_[static_cast<std::size_t>(row) * w + c] =
          static_cast<float>(std::sqrt(rx * rx + ry * ry + 1.0));
    }
  }
  span_u_.resize(padded);
  span_v_.resize(padded);
  span_lod_.resize(padded);
  span_a_.resize(padded);
  span_b_.resize(padded);
  span_fp2_.resize(padded);
  span_z_.resize(padded);
  row_w_stride_ = padded;
  row_w_.resize(4 * padded);
  texture::MipTile::mondrian();  // build the shared tile now rather than inside the first frame
}

void StereoRenderer::render(const Pose3& T_world_left, double time, std::uint64_t frame_id,
                            RenderedFrame& out, bool with_depth) {
  world_.collect(T_world_left.translation(), time, surfaces_);
  render_camera(T_world_left, surfaces_, frame_id, 0, out.left, with_depth ? &out.depth : nullptr);
  Pose3 T_world_right = T_world_left;
  T_world_right.translation() += T_world_left.linear() * Eigen::Vector3d(calib_.baseline, 0.0, 0.0);
  render_camera(T_world_right, surfaces_, frame_id, 1, out.right, nullptr);
}

struct StereoRenderer::ShadeState {
  ShadeState(std::uint64_t seed_a, std::uint64_t seed_b, float sigma) : noise(seed_a, seed_b, sigma) {}
  PixelNoise noise;
  float upx = 0.0f, upy = 0.0f, upz = 0.0f;  // world up in the camera frame (sky shading)
  double vig = 0.0;                          // vignetting / r_corner²
  float inv_fx2 = 0.0f;
  float g = 0.0f;  // 255 · exposure gain
};

void StereoRenderer::render_camera(const Pose3& T_world_cam, const SurfaceList& surfaces,
                                   std::uint64_t frame_id, int camera, cv::Mat& image, cv::Mat* depth) {
  prepare(T_world_cam.inverse(), surfaces);

  const int W = calib_.width;
  const int H = calib_.height;
  const double cy = calib_.cy;
  image.create(H, W, CV_8UC1);
  if (depth != nullptr) depth->create(H, W, CV_32FC1);
  const PhotometricOptions& ph = options_.photometric;

  // Per-frame, per-camera exposure and the noise streams.
  RandomStream rng(options_.seed, frame_id * 2 + static_cast<std::uint64_t>(camera));
  const double gain = (ph.exposure_sigma > 0.0 ? std::exp(ph.exposure_sigma * rng.normal()) : 1.0) *
                      (camera == 1 ? ph.right_gain : 1.0);
  // The first draw seeds lanes 2–3, the second lanes 0–1 (the order GCC evaluated the two draws in when they
  // were written as constructor arguments; kept so the images stay the same).
  const std::uint64_t seed_b = rng.engine()();
  const std::uint64_t seed_a = rng.engine()();
  ShadeState state(seed_a, seed_b, static_cast<float>(ph.noise_sigma));

  // Sky: brighter towards the zenith (few features).
  const Eigen::Vector3d up_cam = T_world_cam.linear().transpose() * world_.up();
  state.upx = static_cast<float>(up_cam.x());
  state.upy = static_cast<float>(up_cam.y());
  state.upz = static_cast<float>(up_cam.z());
  const double r_corner2 = std::max(calib_.cx * calib_.cx, (W - calib_.cx) * (W - calib_.cx)) +
                           std::max(cy * cy, (H - cy) * (H - cy));
  state.vig = ph.vignetting / r_corner2;
  state.inv_fx2 = static_cast<float>(1.0 / (calib_.fx * calib_.fx));
  state.g = static_cast<float>(255.0 * gain);

  // Rows in order (the noise streams advance row by row), band by band.
  for (int row_begin = 0; row_begin < H; row_begin += kBandRows) {
    const int row_end = std::min(H, row_begin + kBandRows);
    rasterise_band(row_begin, row_end);
    for (int row = row_begin; row < row_end; ++row) shade_row(row, row_begin, state, image, depth);
  }
}

void StereoRenderer::prepare(const Pose3& T_cam_world, const SurfaceList& surfaces) {
  const int W = calib_.width;
  const int H = calib_.height;
  const double fx = calib_.fx, fy = calib_.fy, cx = calib_.cx, cy = calib_.cy;
  const double near = options_.near_plane;
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

    // Project.
    Prepared p;
    p.m = m;
    double vmin = 1e300, vmax = -1e300;
    for (int i = 0; i < m; ++i) {
      const Vertex& q = poly[static_cast<std::size_t>(i)];
      p.pu[static_cast<std::size_t>(i)] = fx * q.x / q.z + cx;
      p.pv[static_cast<std::size_t>(i)] = fy * q.y / q.z + cy;
      vmin = std::min(vmin, p.pv[static_cast<std::size_t>(i)]);
      vmax = std::max(vmax, p.pv[static_cast<std::size_t>(i)]);
    }
    constexpr double kEps = 1e-3;  // closes cracks between surfaces sharing an edge (rasterise_band)
    p.row0 = std::max(0, static_cast<int>(std::ceil(vmin - kEps)));
    p.row1 = std::min(H - 1, static_cast<int>(std::floor(vmax + kEps)));
    if (p.row0 > p.row1) continue;  // covers no pixel row (nothing is drawn; ids are not used)

    p.texture = texture::prepare_texture(s);
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
    prepared_.push_back(p);
  }
}

void StereoRenderer::rasterise_band(int row_begin, int row_end) {
  const int W = calib_.width;
  const std::size_t band = static_cast<std::size_t>(row_end - row_begin) * static_cast<std::size_t>(W);
  std::fill(inv_depth_.begin(), inv_depth_.begin() + static_cast<std::ptrdiff_t>(band), 0.0f);
  std::fill(surface_id_.begin(), surface_id_.begin() + static_cast<std::ptrdiff_t>(band), -1);
  constexpr double kEps = 1e-3;  // closes cracks between surfaces sharing an edge
  for (std::size_t id = 0; id < prepared_.size(); ++id) {
    const Prepared& p = prepared_[id];
    const int r0 = std::max(p.row0, row_begin);
    const int r1 = std::min(p.row1, row_end - 1);
    const int m = p.m;
    // Pixel spans of the surface in the band's rows.
    int spans = 0;
    std::array<int, kBandRows> span_row, span_col0, span_col1;
    std::array<double, kBandRows> span_w;
    for (int row = r0; row <= r1; ++row) {
      const double y = row;
      double xmin = 1e300, xmax = -1e300;
      for (int i = 0; i < m; ++i) {
        const std::size_t a = static_cast<std::size_t>(i);
        const std::size_t b = static_cast<std::size_t>((i + 1) % m);
        const double ya = p.pv[a], yb2 = p.pv[b];
        if ((ya - kEps > y && yb2 - kEps > y) || (ya + kEps < y && yb2 + kEps < y)) continue;
        if (std::abs(yb2 - ya) < 1e-12) {
          xmin = std::min(xmin, std::min(p.pu[a], p.pu[b]));
          xmax = std::max(xmax, std::max(p.pu[a], p.pu[b]));
        } else {
          const double tt = std::clamp((y - ya) / (yb2 - ya), 0.0, 1.0);
          const double x = p.pu[a] + tt * (p.pu[b] - p.pu[a]);
          xmin = std::min(xmin, x);
          xmax = std::max(xmax, x);
        }
      }
      if (xmin > xmax) continue;
      const int col0 = std::max(0, static_cast<int>(std::ceil(std::max(xmin - kEps, -1.0))));
      const int col1 =
          std::min(W - 1, static_cast<int>(std::floor(std::min(xmax + kEps, static_cast<double>(W)))));
      if (col0 > col1) continue;
      span_row[spans] = row - row_begin;
      span_col0[spans] = col0;
      span_col1[spans] = col1;
      span_w[spans] = p.A * col0 + p.B * y + p.C;
      ++spans;
    }
    // 1/z is stepped in double along each row (w += A from the row's first pixel: the reference sequence of
    // values) and tested in float. The steps of one row form a dependency chain, so four rows are stepped
    // together into row buffers, then each row is depth-tested four pixels at a time (pixels are
    // independent within one surface).
    const auto sid = static_cast<std::int32_t>(id);
    for (int g = 0; g < spans; g += 4) {
      const int rows = std::min(4, spans - g);
      int len = 0;
      double w[4] = {0.0, 0.0, 0.0, 0.0};
      for (int r = 0; r < rows; ++r) {
        len = std::max(len, span_col1[g + r] - span_col0[g + r] + 1);
        w[r] = span_w[g + r];
      }
      float* b0 = row_w_.data();
      float* b1 = b0 + row_w_stride_;
      float* b2 = b1 + row_w_stride_;
      float* b3 = b2 + row_w_stride_;
      double w0 = w[0], w1 = w[1], w2 = w[2], w3 = w[3];
      const double A = p.A;
      for (int k = 0; k < len; ++k) {  // rows past their own length (or absent) step harmlessly
        b0[k] = static_cast<float>(w0);
        b1[k] = static_cast<float>(w1);
        b2[k] = static_cast<float>(w2);
        b3[k] = static_cast<float>(w3);
        w0 += A;
        w1 += A;
        w2 += A;
        w3 += A;
      }
      for (int r = 0; r < rows; ++r) {
        const int col0 = span_col0[g + r];
        const int n = span_col1[g + r] - col0 + 1;
        const std::size_t base = static_cast<std::size_t>(span_row[g + r]) * static_cast<std::size_t>(W) +
                                 static_cast<std::size_t>(col0);
        float* zb = inv_depth_.data() + base;
        std::int32_t* ids = surface_id_.data() + base;
        const float* wf = row_w_.data() + static_cast<std::size_t>(r) * row_w_stride_;
        int k = 0;
#if defined(__SSE2__)
        const __m128i vsid = _mm_set1_epi32(sid);
        for (; k + 4 <= n; k += 4) {
          const __m128 wv = _mm_loadu_ps(wf + k);
          const __m128 zv = _mm_loadu_ps(zb + k);
          const __m128 in_front = _mm_cmpgt_ps(wv, zv);  // wf > zb, false for NaN like the scalar test
          const __m128i mi = _mm_castps_si128(in_front);
          _mm_storeu_ps(zb + k, _mm_or_ps(_mm_and_ps(in_front, wv), _mm_andnot_ps(in_front, zv)));
          const __m128i iv = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ids + k));
          _mm_storeu_si128(reinterpret_cast<__m128i*>(ids + k),
                           _mm_or_si128(_mm_and_si128(mi, vsid), _mm_andnot_si128(mi, iv)));
        }
#endif
        for (; k < n; ++k) {
          if (wf[k] > zb[k]) {
            zb[k] = wf[k];
            ids[k] = sid;
          }
        }
      }
    }
  }
}

void StereoRenderer::shade_row(int row, int row_begin, ShadeState& state, cv::Mat& image, cv::Mat* depth) {
  const int W = calib_.width;
  const double fy = calib_.fy, cy = calib_.cy;
  const float upx = state.upx, upy = state.upy, upz = state.upz;
  const float inv_fx2 = state.inv_fx2;
  const float* rx = ray_x_.data();
  float* albedo = row_albedo_.data();
  std::int32_t* su = span_u_.data();
  std::int32_t* sv = span_v_.data();
  float* slod = span_lod_.data();
  float* sa = span_a_.data();
  float* sb = span_b_.data();
  float* sfp2 = span_fp2_.data();
  float* sz = span_z_.data();

  auto* img = image.ptr<std::uint8_t>(row);
  float* dep = depth != nullptr ? depth->ptr<float>(row) : nullptr;
  const double ry_d = (row - cy) / fy;
  const auto ry = static_cast<float>(ry_d);
  const float ry2p1 = ry * ry + 1.0f;
  const std::size_t base = static_cast<std::size_t>(row) * static_cast<std::size_t>(W);
  const std::int32_t* ids =
      surface_id_.data() + static_cast<std::size_t>(row - row_begin) * static_cast<std::size_t>(W);
  const float* rn = ray_norm_.data() + base;
  int col = 0;
  while (col < W) {
    const std::int32_t id = ids[col];
    int end = col + 1;
#if defined(__SSE2__)
    {
      const __m128i vid = _mm_set1_epi32(id);
      while (end + 4 <= W) {
        const int eq = _mm_movemask_ps(_mm_castsi128_ps(
            _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(ids + end)), vid)));
        if (eq != 0xF) {
          end += __builtin_ctz(static_cast<unsigned>(~eq));
          break;
        }
        end += 4;
      }
    }
#endif
    while (end < W && ids[end] == id) ++end;
    const int n = end - col;
    if (id < 0) {
      const float sky_row = ry * upy + upz;
      int c = col;
#if defined(__SSE2__)
      {
        // std::clamp(e, lo, hi) is std::min(std::max(e, lo), hi); std::max(x, y) ≡ _mm_max_ps(y, x) and
        // std::min(x, y) ≡ _mm_min_ps(y, x), NaN included.
        const __m128 vupx = _mm_set1_ps(upx), vrow = _mm_set1_ps(sky_row), k25 = _mm_set1_ps(2.5f),
                     lo = _mm_set1_ps(-0.5f), hi = _mm_set1_ps(1.0f), b = _mm_set1_ps(0.80f),
                     s = _mm_set1_ps(0.12f);
        for (; c + 4 <= end; c += 4) {
          const __m128 elev =
              _mm_div_ps(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(rx + c), vupx), vrow), _mm_loadu_ps(rn + c));
          const __m128 e = _mm_min_ps(hi, _mm_max_ps(lo, _mm_mul_ps(elev, k25)));
          _mm_storeu_ps(albedo + c, _mm_add_ps(b, _mm_mul_ps(s, e)));
        }
      }
#endif
      for (; c < end; ++c) {
        const float elev = (rx[c] * upx + sky_row) / rn[c];
        albedo[c] = 0.80f + 0.12f * std::clamp(elev * 2.5f, -0.5f, 1.0f);
      }
      if (dep != nullptr) std::fill(dep + col, dep + end, 0.0f);
      col = end;
      continue;
    }
    const Prepared& p = prepared_[static_cast<std::size_t>(id)];
    const texture::SurfaceTexture& t = p.texture;
    // 1/z, a/z and b/z are affine in the pixel coordinates; evaluated in double at the span start and
    // stepped in float inside the span (relative error ~1e-7).
    const double w0 = p.A * col + p.B * row + p.C;
    const double na0 = p.Au * col + p.Bu * row + p.Cu;
    const double nb0 = p.Av * col + p.Bv * row + p.Cv;
    const auto nx = static_cast<float>(p.nx);
    const auto n_row = static_cast<float>(p.ny * ry_d + p.nz);
    if (t.tile != nullptr) {
      // Tile texel coordinates u = ua·a + ub·b + off_u (likewise v), so u/z is affine too.
      const auto w0f = static_cast<float>(w0), dw = static_cast<float>(p.A);
      const auto nu0 = static_cast<float>(t.ua * na0 + t.ub * nb0 + t.off_u * w0);
      const auto du = static_cast<float>(t.ua * p.Au + t.ub * p.Av + t.off_u * p.A);
      const auto nv0 = static_cast<float>(t.va * na0 + t.vb * nb0 + t.off_v * w0);
      const auto dv = static_cast<float>(t.va * p.Au + t.vb * p.Av + t.off_v * p.A);
      const float lod_bias = t.lod_bias;
      const float* rxs = rx + col;
      const float* rns = rn + col;
      int k = 0;
#if defined(__SSE2__)
      {
        const __m128 vw0 = _mm_set1_ps(w0f), vdw = _mm_set1_ps(dw), vnu0 = _mm_set1_ps(nu0),
                     vdu = _mm_set1_ps(du), vnv0 = _mm_set1_ps(nv0), vdv = _mm_set1_ps(dv),
                     vfix = _mm_set1_ps(256.0f), vry2p1 = _mm_set1_ps(ry2p1), vnx = _mm_set1_ps(nx),
                     vnrow = _mm_set1_ps(n_row), vmin = _mm_set1_ps(1e-3f), vfx2 = _mm_set1_ps(inv_fx2),
                     vone = _mm_set1_ps(1.0f), vhalf = _mm_set1_ps(0.5f), vbias = _mm_set1_ps(lod_bias),
                     vabs = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF)), vfour = _mm_set1_ps(4.0f);
        const __m128i mant = _mm_set1_epi32(0x007FFFFF), one_bits = _mm_set1_epi32(0x3F800000),
                      exp_bias = _mm_set1_epi32(127);
        __m128 kf = _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f);
        for (; k + 4 <= n; k += 4, kf = _mm_add_ps(kf, vfour)) {
          const __m128 iz = _mm_div_ps(vone, _mm_add_ps(vw0, _mm_mul_ps(vdw, kf)));
          _mm_storeu_ps(sz + k, iz);
          const __m128 u = _mm_mul_ps(_mm_add_ps(vnu0, _mm_mul_ps(vdu, kf)), iz);
          const __m128 v = _mm_mul_ps(_mm_add_ps(vnv0, _mm_mul_ps(vdv, kf)), iz);
          _mm_storeu_si128(reinterpret_cast<__m128i*>(su + k), _mm_cvttps_epi32(_mm_mul_ps(u, vfix)));
          _mm_storeu_si128(reinterpret_cast<__m128i*>(sv + k), _mm_cvttps_epi32(_mm_mul_ps(v, vfix)));
          const __m128 rxv = _mm_loadu_ps(rxs + k);
          const __m128 r2 = _mm_add_ps(_mm_mul_ps(rxv, rxv), vry2p1);
          const __m128 ndr = _mm_max_ps(_mm_and_ps(_mm_add_ps(_mm_mul_ps(vnx, rxv), vnrow), vabs), vmin);
          const __m128 fp2 = _mm_div_ps(
              _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(_mm_mul_ps(iz, iz), r2), _mm_loadu_ps(rns + k)), vfx2), ndr);
          _mm_storeu_ps(sfp2 + k, fp2);
          const __m128i bits = _mm_castps_si128(fp2);
          const __m128i e = _mm_sub_epi32(_mm_srli_epi32(bits, 23), exp_bias);
          const __m128 m = _mm_castsi128_ps(_mm_or_si128(_mm_and_si128(bits, mant), one_bits));
          const __m128 lg = _mm_add_ps(_mm_cvtepi32_ps(e), _mm_sub_ps(m, vone));
          _mm_storeu_ps(slod + k, _mm_add_ps(_mm_mul_ps(vhalf, lg), vbias));
        }
      }
#endif
      for (; k < n; ++k) {
        const auto kf = static_cast<float>(k);
        const float iz = 1.0f / (w0f + dw * kf);  // depth z
        sz[k] = iz;
        su[k] = texture::MipTile::to_fixed((nu0 + du * kf) * iz);
        sv[k] = texture::MipTile::to_fixed((nv0 + dv * kf) * iz);
        // Squared footprint (metres per pixel on the surface): z·|r|/fx across the ray divided by √cosθ
        // (geometric mean of the two axes on the surface), cosθ = |n·r|/|r|.
        const float r2 = rxs[k] * rxs[k] + ry2p1;
        const float n_dot_r = std::max(std::abs(nx * rxs[k] + n_row), 1e-3f);
        const float fp2 = iz * iz * r2 * rns[k] * inv_fx2 / n_dot_r;
        sfp2[k] = fp2;
        slod[k] = 0.5f * texture::fast_log2(fp2) + lod_bias;
      }
      if (dep != nullptr) std::copy(sz, sz + n, dep + col);
      const texture::MipTile& tile = *t.tile;
      float* out = albedo + col;
      tile.sample_span(su, sv, slod, n, out);
      if (t.kind == TextureKind::kFacade) {
        const auto a0 = static_cast<float>(na0), da = static_cast<float>(p.Au);
        const auto b0 = static_cast<float>(nb0), db = static_cast<float>(p.Av);
        int j = 0;
#if defined(__SSE2__)
        {
          const __m128 va0 = _mm_set1_ps(a0), vda = _mm_set1_ps(da), vb0 = _mm_set1_ps(b0),
                       vdb = _mm_set1_ps(db), vfour = _mm_set1_ps(4.0f);
          __m128 kf = _mm_setr_ps(0.0f, 1.0f, 2.0f, 3.0f);
          for (; j + 4 <= n; j += 4, kf = _mm_add_ps(kf, vfour)) {
            const __m128 iz = _mm_loadu_ps(sz + j);
            _mm_storeu_ps(sa + j, _mm_mul_ps(_mm_add_ps(va0, _mm_mul_ps(vda, kf)), iz));
            _mm_storeu_ps(sb + j, _mm_mul_ps(_mm_add_ps(vb0, _mm_mul_ps(vdb, kf)), iz));
          }
        }
#endif
        for (; j < n; ++j) {
          const auto kf = static_cast<float>(j);
          sa[j] = (a0 + da * kf) * sz[j];
          sb[j] = (b0 + db * kf) * sz[j];
        }
        texture::facade_span(t, sa, sb, sfp2, n, out);
      } else {
        texture::tile_albedo_span(t, n, out);
      }
    } else {
      // Analytic textures (bands, discs, constant): exact per-pixel evaluation in double.
      for (int c = col; c < end; ++c) {
        const double z = 1.0 / (p.A * c + p.B * row + p.C);
        const auto a = static_cast<float>((p.Au * c + p.Bu * row + p.Cu) * z);
        const auto b = static_cast<float>((p.Av * c + p.Bv * row + p.Cv) * z);
        const float r2 = rx[c] * rx[c] + ry2p1;
        const float n_dot_r = std::max(std::abs(nx * rx[c] + n_row), 1e-3f);
        const auto zf = static_cast<float>(z);
        albedo[c] = texture::albedo(t, a, b, zf * zf * r2 * rn[c] * inv_fx2 / n_dot_r);
        if (dep != nullptr) dep[c] = zf;
      }
    }
    col = end;
  }
  // Photometry: exposure gain, vignetting 1 − vig·r², noise, rounding.
  const double dy = row - cy;
  state.noise.apply_row(albedo, vignette_x_.data(), state.g, static_cast<float>(1.0 - state.vig * dy * dy), W,
                        img);
}

}  // namespace glmbslam::sim
