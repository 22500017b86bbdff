#pragma once
// A precomputed, periodic, mip-mapped texture tile: the rectangle pattern ("Mondrian") of the synthetic
// stereo world, evaluated once per process instead of once per pixel. The pattern is the sum of three
// layers of random rectangles (one per square cell, cell sizes 1, 1/3 and 1/9 pattern units, amplitudes 1,
// 0.8, 0.6); the tile covers kPeriod × kPeriod units with kTexelsPerUnit texels per unit and wraps around
// seamlessly (every layer's cell count divides the period and the cell hash is taken modulo it).
//
// Sampling is trilinear (fixed-point coordinates with 1/256 texel resolution): bilinear inside the two mip
// levels bracketing the level of detail lod = log2(pixel footprint in level-0 texels), blended linearly; the
// box-filtered mip levels band-limit the pattern to the footprint, so layers finer than a pixel fade to their
// mean as in the per-pixel procedural version this replaces. A surface samples the tile at (a, b)/scale plus
// a texel offset drawn from its seed, so different surfaces show different parts of it and the same surface
// point always has the same value.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace glmbslam::sim::texture {

class MipTile {
 public:
  static constexpr int kLog2Size = 11;
  static constexpr int kSize = 1 << kLog2Size;          ///< level-0 texels per side
  static constexpr int kTexelsPerUnit = 64;             ///< level-0 texels per pattern unit
  static constexpr int kLevels = kLog2Size + 1;         ///< kSize, kSize/2, …, 1
  static constexpr float kDecodeScale = 4.0f / 255.0f;  ///< value = kDecodeScale·q + kDecodeOffset
  static constexpr float kDecodeOffset = -2.0f;
  static constexpr float kMaxLod = static_cast<float>(kLevels - 1) - 1.0f / 1024.0f;
  static constexpr std::int32_t kFixedPeriodMask = (kSize << 8) - 1;  ///< fixed-point period − 1

  /// The rectangle pattern tile (built on first use, thread-safe; ~5.6 MB).
  static const MipTile& mondrian();

  /// Fixed-point level-0 texel coordinate (texel·256, truncated) of a real texel coordinate. |u| < 2^23.
  static std::int32_t to_fixed(float u) { return static_cast<std::int32_t>(u * 256.0f); }

  /// Trilinear sample at fixed-point level-0 texel coordinates (U, V) (texel·256; texel centres at
  /// integers + 0.5; any value, the tile wraps) and level of detail `lod` (clamped to [0, kLevels − 1]), as
  /// the stored code in [0, 255] (decode with kDecodeScale, kDecodeOffset). The same arithmetic as
  /// sample_span().
  float sample(std::int32_t U, std::int32_t V, float lod) const {
    const float lc = std::min(std::max(lod, 0.0f), kMaxLod);
    const auto l = static_cast<std::int32_t>(lc);
    const float t = lc - static_cast<float>(l);
    const float c0 = bilinear(l, U, V);
    const float c1 = bilinear(l + 1, U, V);
    return c0 + t * (c1 - c0);
  }

  /// out[k] = sample(U[k], V[k], lod[k]) for k < n: eight at a time with AVX2 when the CPU has it (chosen at
  /// run time), else four at a time with SSE2; every path gives the same bits.
  void sample_span(const std::int32_t* U, const std::int32_t* V, const float* lod, int n, float* out) const;
  /// The SSE2 (baseline x86-64) path of sample_span(), whatever the CPU (tests compare the paths).
  void sample_span_baseline(const std::int32_t* U, const std::int32_t* V, const float* lod, int n,
                            float* out) const;
  /// True when sample_span() uses AVX2 on this CPU.
  static bool avx2_enabled();

  /// Bilinear sample of mip level `level` at fixed-point level-0 texel coordinates (U, V).
  float bilinear(std::int32_t level, std::int32_t U, std::int32_t V) const {
    const float s = level_scale_[static_cast<std::size_t>(level)];  // 2^−level
    const float size = static_cast<float>(kSize) * s;
    const auto mask = static_cast<std::uint32_t>(static_cast<std::int32_t>(size) - 1);
    // Level texel coordinates from the first texel centre, in [−0.5, size) after reducing modulo the period.
    const float x = static_cast<float>(U & kFixedPeriodMask) * s * (1.0f / 256.0f) - 0.5f;
    const float y = static_cast<float>(V & kFixedPeriodMask) * s * (1.0f / 256.0f) - 0.5f;
    const std::int32_t xi = static_cast<std::int32_t>(x + 1.0f) - 1;
    const std::int32_t yi = static_cast<std::int32_t>(y + 1.0f) - 1;
    const float fx = x - static_cast<float>(xi);
    const float fy = y - static_cast<float>(yi);
    // Rows are stored with one extra column and one extra row (copies of the first): no wrap for +1.
    const std::uint32_t stride = static_cast<std::uint32_t>(size) + 1U;
    const std::uint32_t x0 = static_cast<std::uint32_t>(xi) & mask;
    const std::uint32_t y0 = static_cast<std::uint32_t>(yi) & mask;
    const std::uint8_t* p =
        data_.data() + offset_[static_cast<std::size_t>(level)] +
        static_cast<std::uint32_t>(static_cast<float>(static_cast<std::int32_t>(y0)) *
                                   static_cast<float>(static_cast<std::int32_t>(stride))) +
        x0;
    const float v00 = p[0], v10 = p[1], v01 = p[stride], v11 = p[stride + 1];
    const float top = v00 + fx * (v10 - v00);
    const float bottom = v01 + fx * (v11 - v01);
    return top + fy * (bottom - top);
  }

  /// Stored code of texel (i, j) of `level` (no wrapping: 0 ≤ i, j < kSize >> level).
  std::uint8_t texel(int level, int i, int j) const {
    const std::size_t stride = static_cast<std::size_t>(kSize >> level) + 1;
    return data_[offset_[static_cast<std::size_t>(level)] + static_cast<std::size_t>(j) * stride +
                 static_cast<std::size_t>(i)];
  }

  /// The pattern value (before quantisation) at pattern coordinates (x, y) (units), box-filtered over
  /// `footprint` units (anti-aliased rectangle edges): what level 0 stores at its texel centres.
  static float pattern(double x, double y, double footprint);

 private:
  MipTile();

  std::vector<std::uint8_t> data_;
  std::array<std::size_t, kLevels> offset_{};
  std::array<float, kLevels> level_scale_{};
  float mean_ = 0.0f;
};

}  // namespace glmbslam::sim::texture
