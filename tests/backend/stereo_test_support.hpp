#pragma once
// Shared fixtures of the stereo backend tests: the KITTI 00-02 camera and ORB-like descriptors.
#include <cstdint>

#include "core/hamming.hpp"
#include "core/random.hpp"
#include "core/types.hpp"

namespace glmbslam::backend::test {

/// KITTI odometry sequences 00-02, left camera (P0/P1 of calib.txt).
inline StereoCalibration kitti_calibration() {
  StereoCalibration c;
  c.fx = c.fy = 718.856;
  c.cx = 607.1928;
  c.cy = 185.2157;
  c.baseline = 386.1448 / 718.856;
  c.width = 1241;
  c.height = 376;
  return c;
}

inline Descriptor256 random_descriptor(RandomStream& rng) {
  Descriptor256 d;
  for (auto& b : d) b = static_cast<std::uint8_t>(rng.index(256));
  return d;
}

/// `bits` bits of d flipped.
inline Descriptor256 flipped(Descriptor256 d, int bits) {
  for (int i = 0; i < bits; ++i)
    d[static_cast<std::size_t>(i / 8)] ^= static_cast<std::uint8_t>(1u << (i % 8));
  return d;
}

}  // namespace glmbslam::backend::test
