#pragma once
// Everything a stereo `glmbslam run` produces, and the writer of its output folder:
//   trajectory.txt      SLAM estimate (KITTI format, one pose per input frame)
//   vo_trajectory.txt   the frontend's visual odometry, accumulated (KITTI format)
//   map.pcd             labelled landmarks of the final MAP estimate with existence probability
//   trajectory_refined.txt, map_refined.pcd   with --refine ml: the RFS-ML refinement's trajectory and map
//   ground_truth.txt    the reference of the metrics, when every frame has one (ground_truth_output.hpp)
//   report.html         the interactive report (eval/html_report.hpp; app/run_report.hpp): opens offline
//   metrics.json        `slam` and `vo` evaluation blocks (when ground truth exists; `refined` too with
//                       --refine ml), `timing`, `map`, `filter` (and `refinement`: its timings and counters)
//   config_used.yaml    the effective configuration
//   plots/              trajectories vs ground truth, errors, map top view (PNG)
// An interrupted run (SIGINT/SIGTERM) writes the same files for the frames it finished: the trajectories hold
// one pose per finished frame and metrics.json says "interrupted": true with the frames requested and the
// last frame done. Interrupted during the refinement's final pass, every frame is there, "interrupted" is
// true and refinement.final_interrupted is 1 (the refined outputs are the pass's last completed round).
#include <map>
#include <string>
#include <vector>

#include <optional>
#include "core/types.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::app {

struct RunRecord {
  std::string dataset_name;
  std::string algorithm;
  int particles = 0;
  std::uint64_t seed = 0;
  std::size_t first_frame = 0;
  PoseList slam_poses;
  PoseList vo_poses;
  std::optional<PoseList> ground_truth;  ///< relative to the first processed frame
  std::vector<char> ground_truth_mask;   ///< per frame: 1 if ground_truth is measured there (empty: all)
  std::vector<io::MapPoint> map;
  std::vector<double> frontend_ms, vo_ms, backend_ms;
  std::vector<double> ess_fraction;  ///< ESS / N per step
  std::vector<int> tracks;           ///< landmarks (tracks of the best particle) after each frame, if known
  std::optional<PoseList> refined_poses;     ///< the refined trajectory (trajectory_refined.txt), if any
  std::vector<io::MapPoint> refined_map;     ///< the refined map (map_refined.pcd), with refined_poses
  std::map<std::string, double> refinement;  ///< the refinement's timings and counters (metrics.json)
  /// the stereo pair's row alignment (metrics.json `rectification`; rectification_check_stage.hpp)
  std::map<std::string, double> rectification;
  /// the right camera's contrast against the left's (metrics.json `stereo_photometry`;
  /// stereo_photometry_stage.hpp)
  std::map<std::string, double> stereo_photometry;
  std::vector<bool> resampled;
  std::size_t vo_fallbacks = 0;
  std::size_t missing_frames = 0;
  /// stopped by SIGINT/SIGTERM before the last requested frame, or during the refinement's final pass
  bool interrupted = false;
  std::size_t frames_requested =
      0;  ///< frames of the requested range (the record holds fewer if interrupted)
  double wall_s = 0.0;
  std::string effective_config;
};

/// Writes the output folder (every file atomically) and prints where the outputs are and the headline
/// metrics. Throws InputError naming the file on a write failure.
void write_run_outputs(const std::string& out_dir, const RunRecord& record, bool plots);

/// Peak resident set size of this process in MiB (VmHWM), 0 if unknown.
double peak_rss_mib();

}  // namespace glmbslam::app
