#include "sim/kitti_sequence_writer.hpp"

#include <atomic>
#include <cctype>
#include <cstdio>
#include <exception>
#include <memory>
#include <mutex>
#include <vector>

#include <unistd.h>
#include <opencv2/imgcodecs.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/stopwatch.hpp"
#include "io/kitti_odometry.hpp"
#include "io/trajectory_io.hpp"
#include "sim/default_trajectory.hpp"
#include "sim/png_writer.hpp"
#include "sim/stereo_procedural_world.hpp"

namespace glmbslam::sim {
namespace fs = std::filesystem;
namespace {

StereoCalibration make_calibration(double fx, double cx, double cy, double fxb, int width, int height) {
  StereoCalibration c;
  c.fx = fx;
  c.fy = fx;
  c.cx = cx;
  c.cy = cy;
  c.baseline = fxb / fx;
  c.width = width;
  c.height = height;
  return c;
}

bool parse_size(const std::string& text, int& width, int& height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) return false;
  if (w <= 0 || h <= 0 || w > 20000 || h > 20000) return false;
  width = w;
  height = h;
  return true;
}

bool parse_index(const std::string& text, std::size_t& out) {
  if (text.empty() || text.size() > 12) return false;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  out = static_cast<std::size_t>(std::stoull(text));
  return true;
}

std::string frame_name(std::size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%06zu.png", i);
  return buf;
}

void write_png(const fs::path& path, const cv::Mat& image, const std::vector<int>& params) {
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), image, params);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path.string(), "cannot write image");
}

void remove_quietly(const fs::path& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
}

}  // namespace

std::vector<int> png_parameters(int level) {
  if (level <= 0) return {cv::IMWRITE_PNG_COMPRESSION, 0};
  return {cv::IMWRITE_PNG_COMPRESSION, std::min(level, 9), cv::IMWRITE_PNG_STRATEGY,
          cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY};
}

PoseList relative_to_first_exact(const PoseList& poses) {
  PoseList out = poses;
  if (poses.empty()) return out;
  const Eigen::Matrix4d inv0 = poses.front().matrix().inverse();
  for (Pose3& T : out) T.matrix() = inv0 * T.matrix();
  return out;
}

StereoCalibration named_kitti_calibration(const std::string& name) {
  if (name == "kitti00-02") return make_calibration(718.856, 607.1928, 185.2157, 386.1448, 1241, 376);
  if (name == "kitti03") return make_calibration(721.5377, 609.5593, 172.854, 387.5744, 1242, 375);
  if (name == "kitti04-12") return make_calibration(707.0912, 601.8873, 183.1104, 379.8145, 1226, 370);
  if (name == "euroc") return make_calibration(458.654, 367.215, 248.375, 458.654 * 0.110, 752, 480);
  throw ConfigError("unknown calibration '" + name +
                    "' (use kitti00-02, kitti03, kitti04-12, euroc or a calib.txt file)");
}

StereoCalibration resolve_calibration(const std::string& name_or_file, const std::string& size) {
  const bool is_file =
      name_or_file.find('/') != std::string::npos || name_or_file.find('.') != std::string::npos;
  if (!is_file) {
    if (!size.empty())
      throw ConfigError("--size applies only to a calibration file, not to '" + name_or_file + "'");
    return named_kitti_calibration(name_or_file);
  }
  if (!fs::is_regular_file(name_or_file)) {
    throw InputError(name_or_file,
                     "calibration file not found (named sets: kitti00-02, kitti03, kitti04-12, euroc)");
  }
  StereoCalibration c = io::read_kitti_odometry_calibration(name_or_file);
  c.width = 1241;
  c.height = 376;
  if (!size.empty() && !parse_size(size, c.width, c.height)) {
    throw ConfigError("image size '" + size + "' is not WIDTHxHEIGHT (e.g. 1241x376)");
  }
  return c;
}

FrameRange parse_frame_range(const std::string& text, std::size_t count, const std::string& source) {
  FrameRange r{0, count};
  if (!text.empty()) {
    const auto colon = text.find(':');
    if (colon == std::string::npos || !parse_index(text.substr(0, colon), r.begin) ||
        (colon + 1 < text.size() && !parse_index(text.substr(colon + 1), r.end))) {
      throw ConfigError("frame range '" + text + "' is not A:B (frames A..B-1) or A:");
    }
  }
  if (r.begin >= r.end || r.end > count) {
    throw InputError(source, "frame range '" + text + "' is empty or outside the trajectory's " +
                                 std::to_string(count) + " frames (0:" + std::to_string(count) + ")");
  }
  return r;
}

void write_kitti_calibration(const fs::path& path, const StereoCalibration& c) {
  write_text_file_atomically(path, [&](std::ostream& out) {
    auto line = [&](const char* key, double tx) {
      char buf[512];
      std::snprintf(buf, sizeof(buf),
                    "%s: %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e %.12e\n", key,
                    c.fx, 0.0, c.cx, tx, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0);
      out << buf;
    };
    line("P0", 0.0);
    line("P1", -c.fx * c.baseline);
    line("P2", 0.0);
    line("P3", -c.fx * c.baseline);
  });
}

SequenceRenderSummary render_kitti_sequence(const SequenceRenderOptions& options) {
  Stopwatch watch;
  if (options.out_dir.empty()) throw ConfigError("render: an output folder (--out) is required");
  if (options.sequence.empty() || options.sequence.size() > 64)
    throw ConfigError("render: bad sequence name");
  for (char c : options.sequence) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') {
      throw ConfigError("render: sequence name '" + options.sequence +
                        "' may hold only letters, digits, '_', '-'");
    }
  }
  if (options.movers < 0) throw ConfigError("render: --movers must be >= 0");
  if (!(options.frame_rate > 0.0)) throw ConfigError("render: frame rate must be positive");
  if (options.png_compression < 0 || options.png_compression > 9) {
    throw ConfigError("render: PNG compression must be in 0..9");
  }
  const std::vector<int> png = png_parameters(options.png_compression);
  const PhotometricOptions& ph = options.photometric;
  if (!(ph.noise_sigma >= 0.0) || !(ph.vignetting >= 0.0 && ph.vignetting < 1.0) ||
      !(ph.exposure_sigma >= 0.0) || !(ph.right_gain > 0.0)) {
    throw ConfigError("render: noise and exposure must be >= 0, vignetting in [0, 1), the right gain > 0");
  }

  // Inputs first: nothing is written before they are all valid.
  const PoseList trajectory = options.poses_path.empty() ? default_trajectory(options.frame_rate)
                                                         : io::read_kitti_poses(options.poses_path);
  const std::string source =
      options.poses_path.empty() ? std::string("default trajectory") : options.poses_path;
  const FrameRange range = parse_frame_range(options.frames, trajectory.size(), source);
  const StereoCalibration calib = resolve_calibration(options.calibration, options.image_size);

  const fs::path out_dir(options.out_dir);
  const fs::path sequences = out_dir / "sequences";
  const fs::path poses_dir = out_dir / "poses";
  ensure_writable_directory(sequences);
  ensure_writable_directory(poses_dir);
  const fs::path final_dir = sequences / options.sequence;
  const fs::path temp_dir =
      sequences / (options.sequence + ".partial." + std::to_string(static_cast<long>(::getpid())));
  remove_quietly(temp_dir);

  // The written frames: the trajectory index each shows and its timestamp (dropped and duplicated frames).
  std::vector<std::size_t> shown;
  std::vector<double> times;
  for (std::size_t i = range.begin; i < range.end; ++i) {
    if (options.drop_every > 0 && (i - range.begin) % options.drop_every == options.drop_every - 1) continue;
    const std::size_t j = shown.size();
    const bool duplicate = options.duplicate_every > 0 && j > 0 && j % options.duplicate_every == 0;
    shown.push_back(duplicate ? shown.back() : i);
    times.push_back(static_cast<double>(options.drop_every > 0 ? i - range.begin : j) / options.frame_rate);
  }

  SequenceRenderSummary summary;
  summary.frames = shown.size();
  summary.sequence_dir = final_dir;
  summary.poses_file = poses_dir / (options.sequence + ".txt");
  try {
    std::error_code ec;
    fs::create_directories(temp_dir, ec);
    if (ec) throw InputError(temp_dir.string(), "cannot create folder (" + ec.message() + ")");
    if (options.images) {
      fs::create_directories(temp_dir / "image_0", ec);
      if (!ec) fs::create_directories(temp_dir / "image_1", ec);
      if (!ec && options.depth) fs::create_directories(temp_dir / "depth_0", ec);
      if (ec) throw InputError(temp_dir.string(), "cannot create image folders (" + ec.message() + ")");

      ProceduralWorldOptions wopt;
      wopt.seed = options.seed;
      wopt.frame_interval = 1.0 / options.frame_rate;
      wopt.movers = options.movers;
      const ProceduralWorld world(trajectory, wopt);
      RenderOptions ropt;
      ropt.photometric = ph;
      ropt.seed = options.seed;

      const auto threads = static_cast<std::size_t>(std::max(1, thread_count()));
      std::vector<std::unique_ptr<StereoRenderer>> renderers(threads);
      std::vector<RenderedFrame> frames(threads);
      std::vector<cv::Mat> depth16(threads);
      std::vector<PngScratch> png_scratch(threads);
      std::mutex mutex;
      std::exception_ptr failure;
      std::atomic<bool> failed{false};
      std::atomic<std::size_t> done{0};
      ProgressReporter progress(summary.frames, "render");
      parallel_for(summary.frames, [&](std::size_t j) {
        if (failed.load()) return;
        try {
          const auto slot = static_cast<std::size_t>(omp_get_thread_num()) % threads;
          if (!renderers[slot]) renderers[slot] = std::make_unique<StereoRenderer>(world, calib, ropt);
          const std::size_t i = shown[j];  // a duplicate renders its source frame again: the same bytes
          RenderedFrame& f = frames[slot];
          renderers[slot]->render(trajectory[i], static_cast<double>(i) / options.frame_rate, i, f,
                                  options.depth);
          if (options.png_compression == 1) {
            write_png_gray8(temp_dir / "image_0" / frame_name(j), f.left, png_scratch[slot]);
            write_png_gray8(temp_dir / "image_1" / frame_name(j), f.right, png_scratch[slot]);
          } else {
            write_png(temp_dir / "image_0" / frame_name(j), f.left, png);
            write_png(temp_dir / "image_1" / frame_name(j), f.right, png);
          }
          if (options.depth) {
            cv::Mat& d16 = depth16[slot];
            d16.create(f.depth.rows, f.depth.cols, CV_16UC1);
            for (int r = 0; r < f.depth.rows; ++r) {
              const float* src = f.depth.ptr<float>(r);
              auto* dst = d16.ptr<std::uint16_t>(r);
              for (int c = 0; c < f.depth.cols; ++c) {
                const double v = std::round(static_cast<double>(src[c]) * 256.0);
                dst[c] = v > 0.0 && v <= 65535.0 ? static_cast<std::uint16_t>(v) : 0;
              }
            }
            write_png(temp_dir / "depth_0" / frame_name(j), d16, png);
          }
          const std::size_t n = ++done;
          std::lock_guard<std::mutex> lock(mutex);
          progress.update(n);
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex);
          if (!failure) failure = std::current_exception();
          failed.store(true);
        }
      });
      if (failure) std::rethrow_exception(failure);
      progress.finish();
    }
    write_kitti_calibration(temp_dir / "calib.txt", calib);
    write_text_file_atomically(temp_dir / "times.txt", [&](std::ostream& out) {
      char buf[64];
      for (std::size_t j = 0; j < summary.frames; ++j) {
        std::snprintf(buf, sizeof(buf), "%.6e\n", times[j]);
        out << buf;
      }
    });
    PoseList used;
    for (std::size_t i : shown) used.push_back(trajectory[i]);
    io::write_kitti_poses(summary.poses_file.string(), relative_to_first_exact(used));
    // Swap the complete folder in.
    const fs::path old_dir =
        sequences / (options.sequence + ".old." + std::to_string(static_cast<long>(::getpid())));
    if (fs::exists(final_dir)) {
      fs::rename(final_dir, old_dir, ec);
      if (ec)
        throw InputError(final_dir.string(), "cannot replace the existing sequence (" + ec.message() + ")");
    }
    fs::rename(temp_dir, final_dir, ec);
    if (ec)
      throw InputError(final_dir.string(), "cannot rename the finished sequence (" + ec.message() + ")");
    remove_quietly(old_dir);
  } catch (...) {
    remove_quietly(temp_dir);
    throw;
  }
  summary.seconds = watch.elapsed_ms() / 1000.0;
  return summary;
}

}  // namespace glmbslam::sim
