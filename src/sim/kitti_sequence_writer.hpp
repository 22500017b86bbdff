#pragma once
// `glmbslam render`: renders a synthetic stereo sequence in the KITTI odometry layout,
//   OUT/sequences/XX/{image_0,image_1}/NNNNNN.png, calib.txt (P0..P3), times.txt (10 Hz),
//   OUT/sequences/XX/depth_0/NNNNNN.png (optional: left depth, uint16 = metres·256, 0 = sky / beyond 255 m),
//   OUT/poses/XX.txt (the trajectory used, relative to its first rendered frame),
// so every other command reads it as a KITTI odometry sequence. The sequence folder is written under a
// temporary name and renamed when complete: a folder named XX is always a complete sequence.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "sim/stereo_renderer.hpp"

namespace glmbslam::sim {

/// The calibration of a named set: "kitti00-02" (1241×376), "kitti03" (1242×375), "kitti04-12" (1226×370),
/// or "euroc" (the EuRoC MAV rig rectified: 752×480, f = 458 px, baseline 0.110 m). Throws ConfigError
/// naming the known sets for any other name.
StereoCalibration named_kitti_calibration(const std::string& name);

/// A named set, or a KITTI calib.txt file (P0/P1 read by io::read_kitti_odometry_calibration) with the image
/// size from `size` ("WxH"; default 1241x376 for a file). Throws ConfigError / InputError.
StereoCalibration resolve_calibration(const std::string& name_or_file, const std::string& size = "");

/// Half-open frame range [begin, end).
struct FrameRange {
  std::size_t begin = 0;
  std::size_t end = 0;
};

/// Parses "A:B" (frames A..B−1), "A:" (A to the end) or "" (all) for a trajectory of `count` frames.
/// Throws InputError naming `source` (the pose file) if the range is empty or outside [0, count).
FrameRange parse_frame_range(const std::string& text, std::size_t count, const std::string& source);

/// T_0^{-1}·T_i with the exact 4×4 inverse (not the rigid-transform inverse), so the first pose is the
/// identity to rounding even when the input rotations are orthonormal only to a few 1e-7 (KITTI files):
/// readers that re-express poses relative to the first then leave them unchanged.
PoseList relative_to_first_exact(const PoseList& poses);

/// OpenCV PNG parameters for a zlib level 0–9 (level ≥ 1 uses Huffman-only coding: on noisy rendered images
/// it is faster and smaller than the default strategy). The sequence writer uses them for the depth images
/// and for image levels other than 1; level 1 (the default) writes the images with the built-in fast encoder
/// (png_writer.hpp: Sub filter + Huffman-only deflate, about 5× faster than libpng at a similar size).
std::vector<int> png_parameters(int level);

/// Writes a KITTI odometry calib.txt: P0 = [fx 0 cx 0; 0 fy cy 0; 0 0 1 0], P1 = P0 with P1[0,3] = −fx·b,
/// P2 = P0, P3 = P1 (the renderer has no colour cameras). Atomic.
void write_kitti_calibration(const std::filesystem::path& path, const StereoCalibration& calibration);

struct SequenceRenderOptions {
  std::string out_dir;                     ///< required
  std::string poses_path;                  ///< KITTI pose file; empty = built-in default trajectory
  std::string calibration = "kitti00-02";  ///< named set or calib file
  std::string image_size;                  ///< "WxH", only with a calib file
  std::string frames;                      ///< "A:B" (half-open), "A:" or "" (all)
  std::uint64_t seed = 1;
  std::string sequence = "00";  ///< folder name XX (letters, digits, '_' or '-')
  int movers = 0;
  bool depth = false;  ///< also write depth_0/
  bool images = true;  ///< false: only calib.txt, times.txt and the poses (dry run, no image folders)
  PhotometricOptions photometric;
  double frame_rate = 10.0;  ///< Hz (times.txt and the movers' timing)
  /// > 0: every n-th written frame (n, 2n, …) repeats the previous one byte for byte (images and pose; a
  /// duplicated frame in a log), its timestamp on the regular grid.
  std::size_t duplicate_every = 0;
  /// > 0: every n-th frame of the range (n−1, 2n−1, …) is left out; the others keep their timestamps, so
  /// times.txt shows the gaps (dropped frames).
  std::size_t drop_every = 0;
  int png_compression = 1;  ///< zlib level 0 (fastest, largest) … 9
};

struct SequenceRenderSummary {
  std::size_t frames = 0;
  std::filesystem::path sequence_dir;
  std::filesystem::path poses_file;
  double seconds = 0.0;  ///< wall time of rendering and writing
};

/// Renders and writes the sequence (parallel over frames; each frame is deterministic given the seed, so the
/// output does not depend on the thread count). Throws InputError / ConfigError on bad input; on any failure
/// the temporary sequence folder is removed.
SequenceRenderSummary render_kitti_sequence(const SequenceRenderOptions& options);

}  // namespace glmbslam::sim
