#pragma once
// Hamming distance between 256-bit binary descriptors (ORB), shared by the frontend (matching) and the
// backend (appearance likelihood).
#include <array>
#include <cstdint>

namespace glmbslam {

using Descriptor256 = std::array<std::uint8_t, 32>;

/// Hamming distance between two 256-bit descriptors. Without the POPCNT instruction in the target flags the
/// compiler's popcount builtin becomes a library call, so the bits are then counted in parallel (SWAR).
inline int hamming_distance(const std::uint8_t* a, const std::uint8_t* b) {
#if defined(__POPCNT__) || !(defined(__x86_64__) || defined(__i386__))
  int d = 0;
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    __builtin_memcpy(&x, a + i, 8);
    __builtin_memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
#else
  std::uint64_t bytes = 0;  // per-byte bit counts of the four words (each byte ends ≤ 32)
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    __builtin_memcpy(&x, a + i, 8);
    __builtin_memcpy(&y, b + i, 8);
    x ^= y;
    x -= (x >> 1) & 0x5555555555555555ULL;
    x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
    bytes += (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
  }
  return static_cast<int>((bytes * 0x0101010101010101ULL) >> 56);
#endif
}

inline int hamming_distance(const Descriptor256& a, const Descriptor256& b) {
  return hamming_distance(a.data(), b.data());
}

}  // namespace glmbslam
