#pragma once
// Rasteriser of the synthetic stereo world: every visible surface is clipped to the near plane, projected
// and scan-converted with a z-buffer (1/z is affine in pixel coordinates on a plane, so depth and texture
// coordinates are exact per pixel); a deferred pass then evaluates the texture once per pixel, row by row in
// spans of one surface. Both passes run band by band (kBandRows rows) so the band's z-buffer stays in the
// cache; the result does not depend on the band size. Pixel centres are at integer coordinates: a
// camera-frame point X appears at u = fx·X/Z + cx, v = fy·Y/Z + cy. The right camera sits at +baseline along
// the left camera's x axis with the same intrinsics (rectified).
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/types.hpp"
#include "sim/render_texture.hpp"
#include "sim/stereo_world.hpp"

namespace glmbslam::sim {

/// Photometric effects (all zero gives a clean, noise-free image).
struct PhotometricOptions {
  double noise_sigma = 2.0;  ///< per-pixel noise σ, grey levels (independent per camera; approximately
                             ///< Gaussian: Irwin–Hall sum of four uniform bytes, pixel_noise.hpp)
  double vignetting = 0.2;  ///< relative darkening at the image corners: gain = 1 − vignetting·(r/r_corner)²
  double exposure_sigma = 0.04;  ///< per-frame, per-camera log-gain standard deviation
  double right_gain =
      1.0;  ///< the right camera's gain relative to the left's (cameras exposed independently)
};

struct RenderOptions {
  PhotometricOptions photometric;
  double near_plane = 0.1;  ///< metres
  std::uint64_t seed = 1;   ///< seeds the photometric noise (the world has its own seed)
};

/// One rendered stereo pair: 8-bit grayscale images and the left camera's depth (CV_32F, metres along the
/// optical axis; 0 where the ray hits no surface, i.e. sky).
struct RenderedFrame {
  cv::Mat left;
  cv::Mat right;
  cv::Mat depth;
};

/// Renders frames of one world with one calibration. Not thread-safe: use one renderer per thread (the world
/// is shared). Buffers are reused between frames.
class StereoRenderer {
 public:
  StereoRenderer(const StereoWorld& world, const StereoCalibration& calibration, RenderOptions options = {});

  /// Renders the stereo pair seen from T_world_left at `time` (seconds; moving objects). `frame_id` keys the
  /// photometric noise and exposure, so a frame is reproducible on its own. `with_depth` fills out.depth.
  void render(const Pose3& T_world_left, double time, std::uint64_t frame_id, RenderedFrame& out,
              bool with_depth = true);

  /// Renders one camera (T_world_cam) of the given surfaces; `camera` (0 left, 1 right) keys the noise.
  /// `depth` may be null.
  void render_camera(const Pose3& T_world_cam, const SurfaceList& surfaces, std::uint64_t frame_id,
                     int camera, cv::Mat& image, cv::Mat* depth);

  const StereoCalibration& calibration() const { return calib_; }

 private:
  struct Prepared {
    texture::SurfaceTexture texture;
    double A, B, C;                // 1/z = A u + B v + C
    double Au, Bu, Cu;             // a/z
    double Av, Bv, Cv;             // b/z
    double nx, ny, nz;             // unit normal in the camera frame
    std::array<double, 8> pu, pv;  // projected polygon (after near clipping), pixels
    int m;                         // its vertex count
    int row0, row1;                // rows it may cover (inclusive), within the image
  };
  /// Per-frame, per-camera photometric state of the shading pass.
  struct ShadeState;
  /// Clips, projects and prepares every surface that may be visible (no pixel work).
  void prepare(const Pose3& T_cam_world, const SurfaceList& surfaces);
  /// Scan-converts the prepared surfaces into the z-buffer of rows [row_begin, row_end) (one band).
  void rasterise_band(int row_begin, int row_end);
  /// Shades one row of the current band into the image (and depth).
  void shade_row(int row, int row_begin, ShadeState& state, cv::Mat& image, cv::Mat* depth);

  /// Rows per band: the z-buffer and surface ids of a band stay in the cache between scan conversion and
  /// shading (the per-pixel result does not depend on the band size).
  static constexpr int kBandRows = 16;

  const StereoWorld& world_;
  StereoCalibration calib_;
  RenderOptions options_;
  SurfaceList surfaces_;
  std::vector<Prepared> prepared_;
  std::vector<float> inv_depth_;          // z-buffer of one band (1/z, 0 = nothing)
  std::vector<std::int32_t> surface_id_;  // index into prepared_ per pixel of one band (−1 = sky)
  std::vector<float> ray_x_;              // (u − cx)/fx per column
  std::vector<float> ray_norm_;           // |(x, y, 1)| of every pixel's ray
  std::vector<float> vignette_x_;  // vignetting·(u − cx)²/r_corner² per column (padded to a multiple of 4)
  std::vector<float> row_albedo_;  // albedo of one row before the photometric effects (padded)
  // Span scratch: fixed-point tile coordinates, level of detail, metres on the surface, squared footprint,
  // depth (padded to a multiple of 4).
  std::vector<std::int32_t> span_u_, span_v_;
  std::vector<float> span_lod_, span_a_, span_b_, span_fp2_, span_z_;
  // Scan conversion scratch: 1/z (float) of four rows of one surface, row_w_stride_ apart.
  std::vector<float> row_w_;
  std::size_t row_w_stride_ = 0;
};

}  // namespace glmbslam::sim
