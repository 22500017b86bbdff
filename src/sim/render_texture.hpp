#pragma once
// Textures of the synthetic stereo world: deterministic functions of the texture coordinates (a, b) (metres
// on the surface) and the surface seed, so the same world point always has the same albedo (a revisited
// place looks the same). Each pattern is band-limited by the pixel footprint (metres covered by one pixel on
// the surface): the rectangle pattern ("Mondrian", texture_tile.hpp) is a precomputed mip-mapped tile
// sampled trilinearly at the footprint's level of detail; window grids, bands and discs are evaluated
// analytically with their edges blurred over one footprint (analytic anti-aliasing), which keeps corners
// stable from frame to frame.
//
// Per surface and frame a SurfaceTexture is prepared once (tile offsets, gains, scales); the per-pixel
// albedo() is then a handful of arithmetic operations and one trilinear tile lookup.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "sim/stereo_world.hpp"
#include "sim/texture_tile.hpp"

namespace glmbslam::sim::texture {

/// 32-bit integer hash (lowbias32 finaliser).
inline std::uint32_t mix32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// Hash of a lattice cell and a seed.
inline std::uint32_t hash_cell(std::int32_t i, std::int32_t j, std::uint32_t seed) {
  return mix32(mix32(seed ^ (static_cast<std::uint32_t>(i) * 0x9E3779B1U)) +
               static_cast<std::uint32_t>(j) * 0x85EBCA77U);
}

/// Uniform in [0, 1) from the top 24 bits.
inline float unit(std::uint32_t h) {
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

inline float clamp01(float x) {
  return std::min(1.0f, std::max(0.0f, x));
}

/// floor() as an integer without a library call (baseline x86-64 has no SSE4.1 rounding instruction).
/// Valid for |x| < 2^31.
inline std::int32_t fast_floor(float x) {
  const auto i = static_cast<std::int32_t>(x);
  return i - static_cast<std::int32_t>(x < static_cast<float>(i));
}

/// Piecewise-linear log2 of a positive normal float (exact at powers of two, continuous, monotone, error
/// below 0.09): enough to pick a mip level.
inline float fast_log2(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof(bits));
  const auto e = static_cast<std::int32_t>(bits >> 23) - 127;
  const std::uint32_t mbits = (bits & 0x007FFFFFU) | 0x3F800000U;
  float m;
  std::memcpy(&m, &mbits, sizeof(m));
  return static_cast<float>(e) + (m - 1.0f);
}

/// Weight of a pattern layer of characteristic size `scale` for footprint `fp`: 0 below 4 pixels, 1 above 8.
inline float layer_weight(float scale, float fp) {
  return clamp01(scale / (4.0f * fp) - 1.0f);
}

/// Per-surface texture parameters, prepared once per frame.
struct SurfaceTexture {
  TextureKind kind = TextureKind::kConstant;
  float albedo = 0.5f;
  float contrast = 0.0f;
  float param0 = 1.0f;
  float param1 = 1.0f;
  std::uint32_t seed = 0;
  // Rectangle tile: value = tile_base + tile_gain·code at texel coordinates (u, v): the surface axes scaled
  // to texels, possibly mirrored and swapped, plus an offset (all drawn from the seed).
  const MipTile* tile = nullptr;  ///< null: no rectangle pattern
  float tile_base = 0.0f;
  float tile_gain = 0.0f;
  float ua = 1.0f, ub = 0.0f, va = 0.0f, vb = 1.0f;  // (u, v) = [ua ub; va vb]·(a, b) + off, texels
  float off_u = 0.0f, off_v = 0.0f;
  float lod_bias = 0.0f;  // log2(texels per metre)
  // Façade windows.
  float inv_param0 = 1.0f, inv_param1 = 1.0f;
  float window_half_cell = 0.0f;  // min(param0, param1)/2
};

/// Texel scale of the rectangle pattern on a surface of kind `kind`: metres per pattern unit.
inline float pattern_scale(const Surface& s) {
  switch (s.kind) {
    case TextureKind::kGround:
    case TextureKind::kFacade:
      return 0.9f;
    case TextureKind::kMondrian:
      return s.param0;
    case TextureKind::kFoliage:
      return 0.7f;
    default:
      return 1.0f;
  }
}

inline SurfaceTexture prepare_texture(const Surface& s) {
  SurfaceTexture t;
  t.kind = s.kind;
  t.albedo = s.albedo;
  t.contrast = s.contrast;
  t.param0 = s.param0;
  t.param1 = s.param1;
  t.seed = s.seed;
  t.inv_param0 = 1.0f / s.param0;
  t.inv_param1 = 1.0f / s.param1;
  t.window_half_cell = 0.5f * std::min(s.param0, s.param1);
  float amplitude = 0.0f;
  bool patterned = true;
  switch (s.kind) {
    case TextureKind::kGround:
      amplitude = 0.9f * s.contrast;
      break;
    case TextureKind::kFacade:
      amplitude = 0.5f * s.contrast;
      break;
    case TextureKind::kMondrian:
    case TextureKind::kFoliage:
      amplitude = s.contrast;
      break;
    default:
      patterned = false;
      break;
  }
  if (patterned) {
    t.tile = &MipTile::mondrian();
    t.tile_base = s.albedo + amplitude * MipTile::kDecodeOffset;
    t.tile_gain = amplitude * MipTile::kDecodeScale;
    const float texels_per_metre = static_cast<float>(MipTile::kTexelsPerUnit) / pattern_scale(s);
    const std::uint32_t h = mix32(s.seed ^ 0xA511E9B3U);
    const auto mask = static_cast<std::uint32_t>(MipTile::kSize - 1);
    t.off_u = static_cast<float>(h & mask);
    t.off_v = static_cast<float>((h >> MipTile::kLog2Size) & mask);
    const float su = ((h >> 29) & 1U) != 0 ? -texels_per_metre : texels_per_metre;
    const float sv = ((h >> 30) & 1U) != 0 ? -texels_per_metre : texels_per_metre;
    if (((h >> 28) & 1U) != 0) {
      t.ua = 0.0f, t.ub = sv, t.va = su, t.vb = 0.0f;
    } else {
      t.ua = su, t.ub = 0.0f, t.va = 0.0f, t.vb = sv;
    }
    t.lod_bias = std::log2(texels_per_metre);
  }
  return t;
}

/// Rectangle tile contribution (albedo units) at (a, b) for the squared footprint fp2 (metres²).
inline float tile_albedo(const SurfaceTexture& t, float a, float b, float fp2) {
  const float lod = 0.5f * fast_log2(fp2) + t.lod_bias;
  const float u = t.ua * a + t.ub * b + t.off_u;
  const float v = t.va * a + t.vb * b + t.off_v;
  return t.tile_base + t.tile_gain * t.tile->sample(MipTile::to_fixed(u), MipTile::to_fixed(v), lod);
}

/// Façade windows: a grid of cells param0 × param1 metres, each with a window (dark glass, some lit) over
/// the background value v; faded out below 4 pixels per half cell, edges blurred over one footprint.
inline float facade_windows(const SurfaceTexture& t, float v, float a, float b, float fp2) {
  const float inv_fp = 1.0f / std::sqrt(fp2);
  const float ww = clamp01(t.window_half_cell * 0.25f * inv_fp - 1.0f);  // layer_weight(min(cw, ch)/2, fp)
  if (ww > 0.0f) {
    const float cw = t.param0;
    const float ch = t.param1;
    const float ga = a * t.inv_param0;
    const float gb = b * t.inv_param1;
    const std::int32_t ia = fast_floor(ga);
    const std::int32_t ib = fast_floor(gb);
    const float la = (ga - static_cast<float>(ia)) * cw;
    const float lb = (gb - static_cast<float>(ib)) * ch;
    const float cx = clamp01(std::min(la - 0.22f * cw, 0.78f * cw - la) * inv_fp + 0.5f);
    const float cy = clamp01(std::min(lb - 0.25f * ch, 0.80f * ch - lb) * inv_fp + 0.5f);
    const float cover = ww * cx * cy;
    if (cover > 0.0f) {  // inside (or on the blurred edge of) the window of this cell
      const float r = unit(hash_cell(ia, ib, t.seed + 7U));
      const float glass = r < 0.7f ? 0.06f + 0.3f * r : 0.55f + 1.2f * (r - 0.7f);
      v += cover * (glass - v);
    }
  }
  return v;
}

/// Albedo in [0, 1] at texture coordinates (a, b) for the squared pixel footprint fp2 (metres²).
inline float albedo(const SurfaceTexture& t, float a, float b, float fp2) {
  float v = t.tile != nullptr ? tile_albedo(t, a, b, fp2) : t.albedo;
  switch (t.kind) {
    case TextureKind::kFacade:
      v = facade_windows(t, v, a, b, fp2);
      break;
    case TextureKind::kBands: {
      const float p = t.param0;
      const float fp = std::sqrt(fp2);
      const float w = layer_weight(p * 0.5f, fp);
      if (w > 0.0f) {
        const float q = b / p;
        const float fr = q - static_cast<float>(fast_floor(q));
        const float sd = fr < 0.5f ? std::min(fr, 0.5f - fr) * p : -std::min(fr - 0.5f, 1.0f - fr) * p;
        const float cov = clamp01(sd / fp + 0.5f);
        v += t.contrast * w * (2.0f * cov - 1.0f);
      }
      break;
    }
    case TextureKind::kDisc: {
      const float d = std::sqrt(a * a + b * b);
      v += t.contrast * clamp01((t.param0 - d) / std::sqrt(fp2) + 0.5f);
      break;
    }
    default:
      break;
  }
  return clamp01(v);
}

}  // namespace glmbslam::sim::texture
