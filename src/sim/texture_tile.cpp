#include "sim/texture_tile.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define GLMBSLAM_TILE_AVX2 1  // an AVX2 sample_span() chosen at run time (the build targets baseline x86-64)
#endif

#include "sim/render_texture.hpp"

namespace glmbslam::sim::texture {
namespace {

constexpr int kPeriodUnits = MipTile::kSize / MipTile::kTexelsPerUnit;  // 32 pattern units

/// One rectangle per square cell of size `cell` (units; `cells` of them per period), random extent and
/// signed intensity in [−1, 1] on a zero background; edges box-filtered over `footprint` units.
double rect_layer_periodic(double x, double y, double cell, int cells, std::uint32_t seed, double footprint) {
  const double gx = x / cell, gy = y / cell;
  // floor() without a library call (baseline x86-64 has no rounding instruction); |g| < 2^31 here.
  auto floor_of = [](double g) {
    const auto i = static_cast<double>(static_cast<std::int32_t>(g));
    return i > g ? i - 1.0 : i;
  };
  const double fx = floor_of(gx), fy = floor_of(gy);
  const double lx = gx - fx, ly = gy - fy;
  auto wrap = [cells](double f) {
    const std::int32_t i = static_cast<std::int32_t>(f) % cells;
    return i < 0 ? i + cells : i;
  };
  const std::uint32_t h = hash_cell(wrap(fx), wrap(fy), seed);
  constexpr double k = 0.36 / 255.0;
  const double x0 = 0.04 + k * static_cast<double>(h & 0xFFU);
  const double x1 = 0.60 + k * static_cast<double>((h >> 8) & 0xFFU);
  const double y0 = 0.04 + k * static_cast<double>((h >> 16) & 0xFFU);
  const double y1 = 0.60 + k * static_cast<double>(h >> 24);
  const double scale = cell / footprint;  // cell units → footprints
  const double cx = std::clamp(std::min(lx - x0, x1 - lx) * scale + 0.5, 0.0, 1.0);
  const double cy = std::clamp(std::min(ly - y0, y1 - ly) * scale + 0.5, 0.0, 1.0);
  const double v = 2.0 * static_cast<double>(unit(mix32(h + 0x68E31DA4U))) - 1.0;
  return v * cx * cy;
}

}  // namespace

float MipTile::pattern(double x, double y, double footprint) {
  double v = rect_layer_periodic(x, y, 1.0, kPeriodUnits, 0x2F6B1D3AU, footprint);
  v += 0.8 * rect_layer_periodic(x + 0.37, y + 0.11, 1.0 / 3.0, 3 * kPeriodUnits, 0x5A1C9E47U, footprint);
  v += 0.6 * rect_layer_periodic(x, y, 1.0 / 9.0, 9 * kPeriodUnits, 0x0D93B2E5U, footprint);
  return static_cast<float>(v);
}

const MipTile& MipTile::mondrian() {
  static const MipTile tile;
  return tile;
}

MipTile::MipTile() {
  std::size_t total = 0;
  for (int l = 0; l < kLevels; ++l) {
    offset_[static_cast<std::size_t>(l)] = total;
    const std::size_t n = static_cast<std::size_t>(kSize >> l) + 1;  // one extra column and row
    total += n * n;
    level_scale_[static_cast<std::size_t>(l)] = 1.0f / static_cast<float>(1 << l);
  }
  data_.resize(total + 4);  // padding: the AVX2 path gathers 4 bytes for each 2-byte texel pair
  // Level 0 in floating point at the texel centres, then 2×2 box averages.
  std::vector<float> level(static_cast<std::size_t>(kSize) * kSize);
  const double texel = 1.0 / kTexelsPerUnit;
  for (int j = 0; j < kSize; ++j) {
    for (int i = 0; i < kSize; ++i) {
      level[static_cast<std::size_t>(j) * kSize + static_cast<std::size_t>(i)] =
          pattern((i + 0.5) * texel, (j + 0.5) * texel, texel);
    }
  }
  std::vector<float> next;
  for (int l = 0; l < kLevels; ++l) {
    const int n = kSize >> l;
    std::uint8_t* out = data_.data() + offset_[static_cast<std::size_t>(l)];
    const std::size_t stride = static_cast<std::size_t>(n) + 1;
    for (std::size_t j = 0; j <= static_cast<std::size_t>(n); ++j) {
      for (std::size_t i = 0; i <= static_cast<std::size_t>(n); ++i) {
        const std::size_t k = (j % static_cast<std::size_t>(n)) * static_cast<std::size_t>(n) +
                              i % static_cast<std::size_t>(n);  // wrapped copy in the extra row/column
        const float q = std::clamp((level[k] - kDecodeOffset) / kDecodeScale, 0.0f, 255.0f);
        out[j * stride + i] = static_cast<std::uint8_t>(q + 0.5f);
      }
    }
    if (n == 1) {
      mean_ = (level[0] - kDecodeOffset) / kDecodeScale;
      break;
    }
    const int m = n / 2;
    next.assign(static_cast<std::size_t>(m) * static_cast<std::size_t>(m), 0.0f);
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        const std::size_t a =
            static_cast<std::size_t>(2 * j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(2 * i);
        next[static_cast<std::size_t>(j) * static_cast<std::size_t>(m) + static_cast<std::size_t>(i)] =
            0.25f * (level[a] + level[a + 1] + level[a + static_cast<std::size_t>(n)] +
                     level[a + static_cast<std::size_t>(n) + 1]);
      }
    }
    level.swap(next);
  }
}

#if defined(GLMBSLAM_TILE_AVX2)
namespace {

/// sample_span() eight pixels at a time with AVX2: the same operations as the SSE2 path, lane for lane (no
/// FMA: the target is "avx2" only, so multiplies and adds are not contracted), and the texel pairs fetched
/// with two gathers per mip level (4-byte loads; the tile data are padded). Returns the pixels done.
__attribute__((target("avx2"))) int sample_span_avx2(const std::uint8_t* data, const std::int32_t* U,
                                                     const std::int32_t* V, const float* lod, int n,
                                                     float* out) {
  constexpr int kSize = MipTile::kSize;
  const __m256 zero = _mm256_setzero_ps(), max_lod = _mm256_set1_ps(MipTile::kMaxLod),
               one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f),
               inv256 = _mm256_set1_ps(1.0f / 256.0f), full = _mm256_set1_ps(static_cast<float>(kSize));
  const __m256i four_full_i = _mm256_set1_epi32(4 * kSize),
                period = _mm256_set1_epi32(MipTile::kFixedPeriodMask), ione = _mm256_set1_epi32(1),
                exp127 = _mm256_set1_epi32(127), byte = _mm256_set1_epi32(0xFF),
                izero = _mm256_setzero_si256(), powers4 = _mm256_set1_epi32(0x555555);
  const auto* base = reinterpret_cast<const int*>(data);
  int k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m256 lc = _mm256_min_ps(_mm256_max_ps(_mm256_loadu_ps(lod + k), zero), max_lod);
    const __m256i l = _mm256_cvttps_epi32(lc);
    const __m256 t = _mm256_sub_ps(lc, _mm256_cvtepi32_ps(l));
    const __m256 um = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(
                                        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(U + k)), period)),
                                    inv256);
    const __m256 vm = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(
                                        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(V + k)), period)),
                                    inv256);
    __m256 c[2];
    for (int j = 0; j < 2; ++j) {
      const __m256i level = _mm256_add_epi32(l, _mm256_set1_epi32(j));
      const __m256 s = _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_sub_epi32(exp127, level), 23));
      const __m256 size = _mm256_mul_ps(full, s);
      const __m256i size_i = _mm256_cvttps_epi32(size);
      const __m256i mask = _mm256_sub_epi32(size_i, ione);
      const __m256i stride = _mm256_add_epi32(size_i, ione);
      const __m256i size4sq = _mm256_madd_epi16(_mm256_slli_epi32(size_i, 1), _mm256_slli_epi32(size_i, 1));
      const __m256i offset =
          _mm256_add_epi32(_mm256_add_epi32(_mm256_and_si256(powers4, _mm256_sub_epi32(izero, size4sq)),
                                            _mm256_sub_epi32(four_full_i, _mm256_slli_epi32(size_i, 2))),
                           level);
      const __m256 x = _mm256_sub_ps(_mm256_mul_ps(um, s), half);
      const __m256 y = _mm256_sub_ps(_mm256_mul_ps(vm, s), half);
      const __m256i xi = _mm256_sub_epi32(_mm256_cvttps_epi32(_mm256_add_ps(x, one)), ione);
      const __m256i yi = _mm256_sub_epi32(_mm256_cvttps_epi32(_mm256_add_ps(y, one)), ione);
      const __m256 fx = _mm256_sub_ps(x, _mm256_cvtepi32_ps(xi));
      const __m256 fy = _mm256_sub_ps(y, _mm256_cvtepi32_ps(yi));
      const __m256i x0 = _mm256_and_si256(xi, mask);
      const __m256i y0 = _mm256_and_si256(yi, mask);
      const __m256i top = _mm256_add_epi32(_mm256_add_epi32(offset, _mm256_madd_epi16(y0, stride)), x0);
      const __m256i g0 = _mm256_i32gather_epi32(base, top, 1);
      const __m256i g1 = _mm256_i32gather_epi32(base, _mm256_add_epi32(top, stride), 1);
      const __m256 v00 = _mm256_cvtepi32_ps(_mm256_and_si256(g0, byte));
      const __m256 v10 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(g0, 8), byte));
      const __m256 v01 = _mm256_cvtepi32_ps(_mm256_and_si256(g1, byte));
      const __m256 v11 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(g1, 8), byte));
      const __m256 top_v = _mm256_add_ps(v00, _mm256_mul_ps(fx, _mm256_sub_ps(v10, v00)));
      const __m256 bottom_v = _mm256_add_ps(v01, _mm256_mul_ps(fx, _mm256_sub_ps(v11, v01)));
      c[j] = _mm256_add_ps(top_v, _mm256_mul_ps(fy, _mm256_sub_ps(bottom_v, top_v)));
    }
    _mm256_storeu_ps(out + k, _mm256_add_ps(c[0], _mm256_mul_ps(t, _mm256_sub_ps(c[1], c[0]))));
  }
  return k;
}

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2") != 0;
  return has;
}

}  // namespace
#endif

bool MipTile::avx2_enabled() {
#if defined(GLMBSLAM_TILE_AVX2)
  return cpu_has_avx2();
#else
  return false;
#endif
}

void MipTile::sample_span(const std::int32_t* U, const std::int32_t* V, const float* lod, int n,
                          float* out) const {
#if defined(GLMBSLAM_TILE_AVX2)
  if (cpu_has_avx2()) {
    const int done = sample_span_avx2(data_.data(), U, V, lod, n, out);
    sample_span_baseline(U + done, V + done, lod + done, n - done, out + done);
    return;
  }
#endif
  sample_span_baseline(U, V, lod, n, out);
}

void MipTile::sample_span_baseline(const std::int32_t* U, const std::int32_t* V, const float* lod, int n,
                                   float* out) const {
  int k = 0;
#if defined(__SSE2__)
  // The arithmetic of sample() and bilinear(), four pixels at a time; texel pairs fetched as 16-bit loads.
  const __m128 zero = _mm_setzero_ps(), max_lod = _mm_set1_ps(kMaxLod), one = _mm_set1_ps(1.0f),
               half = _mm_set1_ps(0.5f), inv256 = _mm_set1_ps(1.0f / 256.0f),
               full = _mm_set1_ps(static_cast<float>(kSize));
  const __m128i four_full_i = _mm_set1_epi32(4 * kSize);
  const __m128i period = _mm_set1_epi32(kFixedPeriodMask), ione = _mm_set1_epi32(1),
                exp127 = _mm_set1_epi32(127), low_bytes = _mm_set1_epi16(0x00FF), izero = _mm_setzero_si128();
  const std::uint8_t* base = data_.data();
  alignas(16) std::int32_t idx[4][4];
  auto pair = [base](std::int32_t i) {
    std::uint16_t v;
    std::memcpy(&v, base + i, 2);
    return static_cast<int>(v);
  };
  for (; k + 4 <= n; k += 4) {
    const __m128 lc = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(lod + k), zero), max_lod);
    const __m128i l = _mm_cvttps_epi32(lc);
    const __m128 t = _mm_sub_ps(lc, _mm_cvtepi32_ps(l));
    const __m128 um = _mm_mul_ps(
        _mm_cvtepi32_ps(_mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(U + k)), period)),
        inv256);
    const __m128 vm = _mm_mul_ps(
        _mm_cvtepi32_ps(_mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(V + k)), period)),
        inv256);
    __m128 f[2][2];
    for (int j = 0; j < 2; ++j) {
      const __m128i level = _mm_add_epi32(l, _mm_set1_epi32(j));
      const __m128 s = _mm_castsi128_ps(_mm_slli_epi32(_mm_sub_epi32(exp127, level), 23));  // 2^−level
      const __m128 size = _mm_mul_ps(full, s);
      const __m128i size_i = _mm_cvttps_epi32(size);
      const __m128i mask = _mm_sub_epi32(size_i, ione);
      const __m128i stride = _mm_add_epi32(size_i, ione);
      // Level offset Σ_{i<level} (kSize/2^i + 1)² = Σ_{i<level} 4^(kLog2Size−i) + 4·kSize − 4·size + level.
      // The first sum, (4·kSize² − 4·size²)/3, is the bit pattern 0101…01 of 4^(kLog2Size) down to
      // 4^(kLog2Size−level+1) = 4·size²: 0x555555 with the bits below 4·size² cleared (kSize = 2^11), i.e.
      // 0x555555 & −(4·size²). All integers below 2^24, so this equals the float computation it replaces.
      static_assert(kLog2Size == 11, "the 0x555555 mask holds the powers of 4 up to 4^11");
      const __m128i size4sq = _mm_madd_epi16(_mm_slli_epi32(size_i, 1), _mm_slli_epi32(size_i, 1));  // ≤ 2^24
      const __m128i offset =
          _mm_add_epi32(_mm_add_epi32(_mm_and_si128(_mm_set1_epi32(0x555555), _mm_sub_epi32(izero, size4sq)),
                                      _mm_sub_epi32(four_full_i, _mm_slli_epi32(size_i, 2))),
                        level);
      // (um·s)·(1/256) in bilinear() equals (um/256)·s: both scalings are exact powers of two.
      const __m128 x = _mm_sub_ps(_mm_mul_ps(um, s), half);
      const __m128 y = _mm_sub_ps(_mm_mul_ps(vm, s), half);
      const __m128i xi = _mm_sub_epi32(_mm_cvttps_epi32(_mm_add_ps(x, one)), ione);
      const __m128i yi = _mm_sub_epi32(_mm_cvttps_epi32(_mm_add_ps(y, one)), ione);
      f[j][0] = _mm_sub_ps(x, _mm_cvtepi32_ps(xi));
      f[j][1] = _mm_sub_ps(y, _mm_cvtepi32_ps(yi));
      const __m128i x0 = _mm_and_si128(xi, mask);
      const __m128i y0 = _mm_and_si128(yi, mask);
      // y0·stride (< 2^23, exact in the float product of bilinear()); both fit in 16 bits: one madd.
      const __m128i row = _mm_madd_epi16(y0, stride);
      const __m128i top = _mm_add_epi32(_mm_add_epi32(offset, row), x0);
      _mm_store_si128(reinterpret_cast<__m128i*>(idx[2 * j]), top);
      _mm_store_si128(reinterpret_cast<__m128i*>(idx[2 * j + 1]), _mm_add_epi32(top, stride));
    }
    __m128 c[2];
    for (int j = 0; j < 2; ++j) {
      // Eight 16-bit texel pairs: lanes 0–3 (v00, v10) of the top row, 4–7 (v01, v11) of the bottom row.
      __m128i pairs = _mm_cvtsi32_si128(pair(idx[2 * j][0]));
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j][1]), 1);
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j][2]), 2);
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j][3]), 3);
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j + 1][0]), 4);
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j + 1][1]), 5);
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j + 1][2]), 6);
      pairs = _mm_insert_epi16(pairs, pair(idx[2 * j + 1][3]), 7);
      const __m128i left = _mm_and_si128(pairs, low_bytes);  // v00 ×4, v01 ×4
      const __m128i right = _mm_srli_epi16(pairs, 8);        // v10 ×4, v11 ×4
      const __m128 v00 = _mm_cvtepi32_ps(_mm_unpacklo_epi16(left, izero));
      const __m128 v01 = _mm_cvtepi32_ps(_mm_unpackhi_epi16(left, izero));
      const __m128 v10 = _mm_cvtepi32_ps(_mm_unpacklo_epi16(right, izero));
      const __m128 v11 = _mm_cvtepi32_ps(_mm_unpackhi_epi16(right, izero));
      const __m128 top = _mm_add_ps(v00, _mm_mul_ps(f[j][0], _mm_sub_ps(v10, v00)));
      const __m128 bottom = _mm_add_ps(v01, _mm_mul_ps(f[j][0], _mm_sub_ps(v11, v01)));
      c[j] = _mm_add_ps(top, _mm_mul_ps(f[j][1], _mm_sub_ps(bottom, top)));
    }
    _mm_storeu_ps(out + k, _mm_add_ps(c[0], _mm_mul_ps(t, _mm_sub_ps(c[1], c[0]))));
  }
#endif
  for (; k < n; ++k) out[k] = sample(U[k], V[k], lod[k]);
}

}  // namespace glmbslam::sim::texture
