// `glmbslam render`: synthetic stereo sequences in the KITTI odometry layout
// (src/sim/kitti_sequence_writer.hpp).
#include <spdlog/spdlog.h>

#include "app/cli_checks.hpp"
#include "app/commands.hpp"
#include "sim/kitti_sequence_writer.hpp"

namespace glmbslam::app {

void register_render_command(CLI::App& app) {
  auto opt = std::make_shared<sim::SequenceRenderOptions>();
  auto* cmd = app.add_subcommand(
      "render",
      "Render a synthetic stereo sequence (KITTI odometry layout, exact ground truth) along a trajectory: "
      "OUT/sequences/XX/{image_0,image_1,calib.txt,times.txt} and OUT/poses/XX.txt");
  cmd->add_option("--out", opt->out_dir, "output folder (gets sequences/XX and poses/XX.txt)")->required();
  cmd->add_option("--poses", opt->poses_path,
                  "KITTI pose file to drive along (default: built-in ~400 m loop with a loop closure)");
  cmd->add_option(
         "--calib", opt->calibration,
         "kitti00-02, kitti03, kitti04-12, euroc (752x480, 0.11 m baseline) or a KITTI calib.txt file")
      ->capture_default_str();
  cmd->add_option("--size", opt->image_size,
                  "image size WIDTHxHEIGHT (only with a calib file; default 1241x376)");
  cmd->add_option("--frames", opt->frames,
                  "frame range A:B of the pose file (frames A..B-1), or A: (default all)");
  cmd->add_option("--seed", opt->seed, "world and noise seed")->capture_default_str();
  cmd->add_option("--rate", opt->frame_rate, "frame rate in Hz (times.txt)")
      ->capture_default_str()
      ->check(positive_number());
  cmd->add_option("--duplicate-every", opt->duplicate_every,
                  "every N-th frame repeats the previous one byte for byte (duplicated frames in a log)");
  cmd->add_option("--drop-every", opt->drop_every,
                  "leave out every N-th frame, the others keep their timestamps (dropped frames)");
  cmd->add_option("--sequence", opt->sequence, "sequence folder name XX")->capture_default_str();
  cmd->add_option("--noise", opt->photometric.noise_sigma, "Gaussian pixel noise sigma (grey levels)")
      ->capture_default_str();
  cmd->add_option("--vignetting", opt->photometric.vignetting, "relative darkening at the corners, in [0, 1)")
      ->capture_default_str();
  cmd->add_option("--exposure", opt->photometric.exposure_sigma, "per-frame log-exposure sigma")
      ->capture_default_str();
  cmd->add_option("--right-gain", opt->photometric.right_gain,
                  "the right camera's gain relative to the left's (independent exposure)")
      ->capture_default_str();
  cmd->add_option("--movers", opt->movers, "number of moving boxes driving along the road")
      ->capture_default_str();
  cmd->add_option("--png-compression", opt->png_compression, "zlib level 0 (fastest, ~2x larger files) to 9")
      ->capture_default_str();
  cmd->add_flag("--depth", opt->depth,
                "also write depth_0/NNNNNN.png (left depth, uint16 metres*256, 0 = sky)");
  cmd->add_flag(
      "--no-images", [opt](std::int64_t) { opt->images = false; },
      "dry run: write only calib.txt, times.txt and the poses");
  cmd->callback([opt] {
    const auto summary = sim::render_kitti_sequence(*opt);
    spdlog::info("rendered {} frames into {} ({:.1f} s, {:.1f} frames/s); poses in {}", summary.frames,
                 summary.sequence_dir.string(), summary.seconds,
                 summary.seconds > 0.0 ? static_cast<double>(summary.frames) / summary.seconds : 0.0,
                 summary.poses_file.string());
  });
}

}  // namespace glmbslam::app
