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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
namespace simd {
// Exact SSE2 counterparts of the scalar helpers: std::max(x, y) ≡ _mm_max_ps(y, x) and std::min(x, y) ≡
// _mm_min_ps(y, x) (the same comparison and the same operand returned, NaN included).
inline __m128 clamp01(__m128 x) {
  return _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(1.0f));
}
/// a·b modulo 2^32 per lane (SSE2 has no 32-bit low multiply).
inline __m128i mullo32(__m128i a, __m128i b) {
  const __m128i even = _mm_mul_epu32(a, b);
  const __m128i odd = _mm_mul_epu32(_mm_srli_epi64(a, 32), _mm_srli_epi64(b, 32));
  return _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                            _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
}
inline __m128i mix32(__m128i x) {
  x = _mm_xor_si128(x, _mm_srli_epi32(x, 16));
  x = mullo32(x, _mm_set1_epi32(0x7feb352d));
  x = _mm_xor_si128(x, _mm_srli_epi32(x, 15));
  x = mullo32(x, _mm_set1_epi32(static_cast<std::int32_t>(0x846ca68bU)));
  return _mm_xor_si128(x, _mm_srli_epi32(x, 16));
}
inline __m128i hash_cell(__m128i i, __m128i j, std::uint32_t seed) {
  const __m128i h = mix32(_mm_xor_si128(_mm_set1_epi32(static_cast<std::int32_t>(seed)),
                                        mullo32(i, _mm_set1_epi32(static_cast<std::int32_t>(0x9E3779B1U)))));
  return mix32(_mm_add_epi32(h, mullo32(j, _mm_set1_epi32(static_cast<std::int32_t>(0x85EBCA77U)))));
}
/// fast_floor() per lane (the truncation and the comparison of the scalar version).
inline __m128i fast_floor(__m128 x) {
  const __m128i i = _mm_cvttps_epi32(x);
  return _mm_add_epi32(i, _mm_castps_si128(_mm_cmplt_ps(x, _mm_cvtepi32_ps(i))));  // −1 where x < i
}
inline __m128 select(__m128 mask, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}
}  // namespace simd
#endif

/// out[k] = facade_windows(t, t.tile_base + t.tile_gain·out[k], a[k], b[k], fp2[k]) clamped to [0, 1], for
/// k < n (`out` holds the tile codes on entry); four pixels at a time with SSE2, identical results.
inline void facade_span(const SurfaceTexture& t, const float* a, const float* b, const float* fp2, int n,
                        float* out) {
  int k = 0;
#if defined(__SSE2__)
  const __m128 base = _mm_set1_ps(t.tile_base), gain = _mm_set1_ps(t.tile_gain), one = _mm_set1_ps(1.0f),
               half = _mm_set1_ps(0.5f), zero = _mm_setzero_ps(),
               whc = _mm_set1_ps(t.window_half_cell * 0.25f), ip0 = _mm_set1_ps(t.inv_param0),
               ip1 = _mm_set1_ps(t.inv_param1), cw = _mm_set1_ps(t.param0), ch = _mm_set1_ps(t.param1),
               cw22 = _mm_set1_ps(0.22f * t.param0), cw78 = _mm_set1_ps(0.78f * t.param0),
               ch25 = _mm_set1_ps(0.25f * t.param1), ch80 = _mm_set1_ps(0.80f * t.param1),
               r07 = _mm_set1_ps(0.7f), g006 = _mm_set1_ps(0.06f), g03 = _mm_set1_ps(0.3f),
               g055 = _mm_set1_ps(0.55f), g12 = _mm_set1_ps(1.2f),
               unit_scale = _mm_set1_ps(1.0f / 16777216.0f);
  for (; k + 4 <= n; k += 4) {
    __m128 v = _mm_add_ps(base, _mm_mul_ps(gain, _mm_loadu_ps(out + k)));
    const __m128 inv_fp = _mm_div_ps(one, _mm_sqrt_ps(_mm_loadu_ps(fp2 + k)));
    const __m128 ww = simd::clamp01(_mm_sub_ps(_mm_mul_ps(whc, inv_fp), one));
    if (_mm_movemask_ps(_mm_cmpgt_ps(ww, zero)) != 0) {
      const __m128 ga = _mm_mul_ps(_mm_loadu_ps(a + k), ip0);
      const __m128 gb = _mm_mul_ps(_mm_loadu_ps(b + k), ip1);
      const __m128i ia = simd::fast_floor(ga);
      const __m128i ib = simd::fast_floor(gb);
      const __m128 la = _mm_mul_ps(_mm_sub_ps(ga, _mm_cvtepi32_ps(ia)), cw);
      const __m128 lb = _mm_mul_ps(_mm_sub_ps(gb, _mm_cvtepi32_ps(ib)), ch);
      // std::min(la − 0.22·cw, 0.78·cw − la) ≡ _mm_min_ps(0.78·cw − la, la − 0.22·cw).
      const __m128 cx = simd::clamp01(
          _mm_add_ps(_mm_mul_ps(_mm_min_ps(_mm_sub_ps(cw78, la), _mm_sub_ps(la, cw22)), inv_fp), half));
      const __m128 cy = simd::clamp01(
          _mm_add_ps(_mm_mul_ps(_mm_min_ps(_mm_sub_ps(ch80, lb), _mm_sub_ps(lb, ch25)), inv_fp), half));
      const __m128 cover = _mm_mul_ps(_mm_mul_ps(ww, cx), cy);
      // Scalar: only where ww > 0 and cover > 0 (cover > 0 implies ww > 0).
      const __m128 inside = _mm_cmpgt_ps(cover, zero);
      if (_mm_movemask_ps(inside) != 0) {
        const __m128i h = simd::hash_cell(ia, ib, t.seed + 7U);
        const __m128 r = _mm_mul_ps(_mm_cvtepi32_ps(_mm_srli_epi32(h, 8)), unit_scale);
        const __m128 glass = simd::select(_mm_cmplt_ps(r, r07), _mm_add_ps(g006, _mm_mul_ps(g03, r)),
                                          _mm_add_ps(g055, _mm_mul_ps(g12, _mm_sub_ps(r, r07))));
        v = simd::select(inside, _mm_add_ps(v, _mm_mul_ps(cover, _mm_sub_ps(glass, v))), v);
      }
    }
    _mm_storeu_ps(out + k, simd::clamp01(v));
  }
#endif
  for (; k < n; ++k) {
    const float v = t.tile_base + t.tile_gain * out[k];
    out[k] = clamp01(facade_windows(t, v, a[k], b[k], fp2[k]));
  }
}

/// out[k] = clamp01(t.tile_base + t.tile_gain·out[k]) for k < n (tile codes to albedo).
inline void tile_albedo_span(const SurfaceTexture& t, int n, float* out) {
  int k = 0;
#if defined(__SSE2__)
  const __m128 base = _mm_set1_ps(t.tile_base), gain = _mm_set1_ps(t.tile_gain);
  for (; k + 4 <= n; k += 4) {
    _mm_storeu_ps(out + k, simd::clamp01(_mm_add_ps(base, _mm_mul_ps(gain, _mm_loadu_ps(out + k)))));
  }
#endif
  for (; k < n; ++k) out[k] = clamp01(t.tile_base + t.tile_gain * out[k]);
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
