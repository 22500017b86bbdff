#pragma once
// Photometric output stage of the synthetic stereo renderer: 8-bit pixel = round(clamp(g·albedo·vignetting +
// noise, 0, 255)), four pixels at a time. The noise is approximately Gaussian with standard deviation
// `sigma`: the sum of the four bytes of a 32-bit xorshift draw (Irwin–Hall, n = 4: mean 510, standard
// deviation 147.80 in byte units, bounded at ±3.45σ), one xorshift stream per lane of four. SSE2 on x86-64,
// the identical scalar computation elsewhere.
#include <algorithm>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace glmbslam::sim {

class PixelNoise {
 public:
  /// Lane states from two 64-bit seeds; sigma ≤ 0 disables the noise.
  PixelNoise(std::uint64_t seed_a, std::uint64_t seed_b, float sigma)
      : scale_(sigma > 0.0f ? sigma / kByteSumSigma : 0.0f), noisy_(sigma > 0.0f) {
    state_[0] = static_cast<std::uint32_t>(seed_a) | 1U;
    state_[1] = static_cast<std::uint32_t>(seed_a >> 32) | 1U;
    state_[2] = static_cast<std::uint32_t>(seed_b) | 1U;
    state_[3] = static_cast<std::uint32_t>(seed_b >> 32) | 1U;
  }

  /// out[c] for c < width from albedo[c] (gain g, vignetting v_row − vig_x[c]). `albedo` and `vig_x` must be
  /// readable up to the next multiple of 4.
  void apply_row(const float* albedo, const float* vig_x, float g, float v_row, int width,
                 std::uint8_t* out) {
#if defined(__SSE2__)
    __m128i s = _mm_loadu_si128(reinterpret_cast<const __m128i*>(state_));
    const __m128 gv = _mm_set1_ps(g), vr = _mm_set1_ps(v_row), sc = _mm_set1_ps(scale_);
    const __m128 mean = _mm_set1_ps(kByteSumMean), lo = _mm_setzero_ps(), hi = _mm_set1_ps(255.0f),
                 half = _mm_set1_ps(0.5f);
    const __m128i bytes = _mm_set1_epi32(0x00FF00FF), low16 = _mm_set1_epi32(0xFFFF);
    for (int c = 0; c < width; c += 4) {
      __m128 v =
          _mm_mul_ps(_mm_mul_ps(gv, _mm_loadu_ps(albedo + c)), _mm_sub_ps(vr, _mm_loadu_ps(vig_x + c)));
      if (noisy_) {
        s = _mm_xor_si128(s, _mm_slli_epi32(s, 13));
        s = _mm_xor_si128(s, _mm_srli_epi32(s, 17));
        s = _mm_xor_si128(s, _mm_slli_epi32(s, 5));
        const __m128i t = _mm_add_epi32(_mm_and_si128(s, bytes), _mm_and_si128(_mm_srli_epi32(s, 8), bytes));
        const __m128i sum = _mm_add_epi32(_mm_and_si128(t, low16), _mm_srli_epi32(t, 16));
        v = _mm_add_ps(v, _mm_mul_ps(_mm_sub_ps(_mm_cvtepi32_ps(sum), mean), sc));
      }
      v = _mm_add_ps(_mm_min_ps(_mm_max_ps(v, lo), hi), half);
      const __m128i i32 = _mm_cvttps_epi32(v);
      const __m128i i16 = _mm_packs_epi32(i32, i32);
      const int packed = _mm_cvtsi128_si32(_mm_packus_epi16(i16, i16));
      if (c + 4 <= width) {
        std::memcpy(out + c, &packed, 4);  // a fixed-size store (a variable-length copy is a byte loop)
      } else {
        std::memcpy(out + c, &packed, static_cast<std::size_t>(width - c));
      }
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(state_), s);
#else
    for (int c = 0; c < width; c += 4) {
      for (int l = 0; l < 4; ++l) {
        float v = g * albedo[c + l] * (v_row - vig_x[c + l]);
        if (noisy_) {
          std::uint32_t& x = state_[l];
          x ^= x << 13;
          x ^= x >> 17;
          x ^= x << 5;
          const std::uint32_t t = (x & 0x00FF00FFU) + ((x >> 8) & 0x00FF00FFU);
          const auto sum = static_cast<std::int32_t>((t & 0xFFFFU) + (t >> 16));
          v = v + (static_cast<float>(sum) - kByteSumMean) * scale_;
        }
        // Same operations as the SSE2 path (max then min, then + 0.5, truncation).
        v = std::min(std::max(v, 0.0f), 255.0f) + 0.5f;
        if (c + l < width) out[c + l] = static_cast<std::uint8_t>(static_cast<std::int32_t>(v));
      }
    }
#endif
  }

 private:
  static constexpr float kByteSumMean = 510.0f;
  static constexpr float kByteSumSigma = 147.80135f;  // √(4·(256² − 1)/12)

  std::uint32_t state_[4];
  float scale_;
  bool noisy_;
};

}  // namespace glmbslam::sim
