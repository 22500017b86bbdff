#pragma once
// Procedural textures of the synthetic stereo world: deterministic functions of the texture coordinates
// (a, b) (metres on the surface) and the surface seed, so the same world point always has the same albedo
// (a revisited place looks the same). Each pattern layer is band-limited by the pixel footprint `fp` (metres
// covered by one pixel on the surface): layers finer than a few pixels fade to their mean, and rectangle
// edges are blurred over one footprint (analytic anti-aliasing), which keeps corners stable from frame to
// frame.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/stereo_world.hpp"

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

/// Weight of a pattern layer of characteristic size `scale` for footprint `fp`: 0 below 4 pixels, 1 above 8.
inline float layer_weight(float scale, float fp) {
  return clamp01(scale / (4.0f * fp) - 1.0f);
}

/// Smooth value noise in [0, 1] with lattice spacing 1.
inline float value_noise(float x, float y, std::uint32_t seed) {
  const std::int32_t ix = fast_floor(x);
  const std::int32_t iy = fast_floor(y);
  float tx = x - static_cast<float>(ix);
  float ty = y - static_cast<float>(iy);
  tx = tx * tx * (3.0f - 2.0f * tx);
  ty = ty * ty * (3.0f - 2.0f * ty);
  const float v00 = unit(hash_cell(ix, iy, seed));
  const float v10 = unit(hash_cell(ix + 1, iy, seed));
  const float v01 = unit(hash_cell(ix, iy + 1, seed));
  const float v11 = unit(hash_cell(ix + 1, iy + 1, seed));
  const float a = v00 + (v10 - v00) * tx;
  const float b = v01 + (v11 - v01) * tx;
  return a + (b - a) * ty;
}

/// One rectangle per square cell of size `cell`, random extent and signed intensity in [−1, 1], on a zero
/// background; edges anti-aliased over the footprint.
inline float rect_layer(float a, float b, float cell, std::uint32_t seed, float inv_fp) {
  const float inv_cell = 1.0f / cell;
  const float ga = a * inv_cell;
  const float gb = b * inv_cell;
  const std::int32_t ia = fast_floor(ga);
  const std::int32_t ib = fast_floor(gb);
  const float la = ga - static_cast<float>(ia);  // in cell units
  const float lb = gb - static_cast<float>(ib);
  const std::uint32_t h = hash_cell(ia, ib, seed);
  constexpr float k = 0.36f / 255.0f;
  const float x0 = 0.04f + k * static_cast<float>(static_cast<std::int32_t>(h & 0xFFU));
  const float x1 = 0.60f + k * static_cast<float>(static_cast<std::int32_t>((h >> 8) & 0xFFU));
  const float y0 = 0.04f + k * static_cast<float>(static_cast<std::int32_t>((h >> 16) & 0xFFU));
  const float y1 = 0.60f + k * static_cast<float>(static_cast<std::int32_t>(h >> 24));
  const float scale = cell * inv_fp;  // cell units → pixels
  const float cx = clamp01(std::min(la - x0, x1 - la) * scale + 0.5f);
  const float cy = clamp01(std::min(lb - y0, y1 - lb) * scale + 0.5f);
  const float v = 2.0f * unit(mix32(h + 0x68E31DA4U)) - 1.0f;
  return v * cx * cy;
}

/// Rectangle layers at three scales (coarse to fine), weighted by the footprint.
inline float mondrian(float a, float b, float scale, std::uint32_t seed, float fp, int layers = 2) {
  const float inv_fp = 1.0f / fp;
  const float q = 0.25f * inv_fp;
  float v = 0.0f;
  float w = clamp01(scale * q - 1.0f);
  if (w > 0.0f) v += w * rect_layer(a, b, scale, seed, inv_fp);
  w = clamp01(0.33f * scale * q - 1.0f);
  if (w > 0.0f)
    v += 0.8f * w * rect_layer(a + 0.37f * scale, b + 0.11f * scale, scale * 0.33f, seed + 1U, inv_fp);
  if (layers < 3) return v;
  w = clamp01(0.11f * scale * q - 1.0f);
  if (w > 0.0f) v += 0.6f * w * rect_layer(a, b, scale * 0.11f, seed + 2U, inv_fp);
  return v;
}

/// Albedo in [0, 1] of surface `s` at texture coordinates (a, b) for pixel footprint `fp` (metres).
inline float albedo(const Surface& s, float a, float b, float fp) {
  const float c = s.contrast;
  float v = s.albedo;
  switch (s.kind) {
    case TextureKind::kConstant:
      break;
    case TextureKind::kGround: {
      v += 0.25f * c * rect_layer(a, b, 4.1f, s.seed + 13U, 1.0f / fp);
      v += 0.9f * c * mondrian(a, b, 0.9f, s.seed + 11U, fp);
      break;
    }
    case TextureKind::kFacade: {
      const float cw = s.param0;
      const float ch = s.param1;
      v += 0.5f * c * mondrian(a, b, 0.9f, s.seed + 3U, fp);
      const float ww = layer_weight(std::min(cw, ch) * 0.5f, fp);
      if (ww > 0.0f) {
        const float ga = a / cw;
        const float gb = b / ch;
        const std::int32_t ia = fast_floor(ga);
        const std::int32_t ib = fast_floor(gb);
        const float la = (ga - static_cast<float>(ia)) * cw;
        const float lb = (gb - static_cast<float>(ib)) * ch;
        const std::uint32_t h = hash_cell(ia, ib, s.seed + 7U);
        const float inv_fp = 1.0f / fp;
        const float cx = clamp01(std::min(la - 0.22f * cw, 0.78f * cw - la) * inv_fp + 0.5f);
        const float cy = clamp01(std::min(lb - 0.25f * ch, 0.80f * ch - lb) * inv_fp + 0.5f);
        const float r = unit(h);
        const float glass = r < 0.7f ? 0.06f + 0.3f * r : 0.55f + 1.2f * (r - 0.7f);
        v += ww * cx * cy * (glass - v);
      }
      break;
    }
    case TextureKind::kMondrian:
      v += c * mondrian(a, b, s.param0, s.seed, fp, 3);
      break;
    case TextureKind::kBands: {
      const float p = s.param0;
      const float w = layer_weight(p * 0.5f, fp);
      if (w > 0.0f) {
        const float t = b / p;
        const float fr = t - static_cast<float>(fast_floor(t));
        const float sd = fr < 0.5f ? std::min(fr, 0.5f - fr) * p : -std::min(fr - 0.5f, 1.0f - fr) * p;
        const float cov = clamp01(sd / fp + 0.5f);
        v += c * w * (2.0f * cov - 1.0f);
      }
      break;
    }
    case TextureKind::kFoliage:
      v += c * mondrian(a, b, 0.7f, s.seed, fp);
      break;
    case TextureKind::kDisc: {
      const float d = std::sqrt(a * a + b * b);
      v += c * clamp01((s.param0 - d) / fp + 0.5f);
      break;
    }
  }
  return clamp01(v);
}

}  // namespace glmbslam::sim::texture
