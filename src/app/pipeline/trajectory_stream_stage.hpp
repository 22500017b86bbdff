#pragma once
// Streams the trajectories while the run goes, so a run killed outright (SIGKILL, out of memory, power cut)
// still leaves every finished frame on disk. Two files in the output folder, one KITTI line per frame, each
// line written and flushed to the disk (fdatasync) as soon as the frame is done:
//   trajectory.streaming.txt      the filter's pose estimate at each frame as it was online (the
//   highest-weight
//                                 particle's current pose; VO when the backend is off)
//   vo_trajectory.streaming.txt   the accumulated visual odometry
// The final trajectory.txt / vo_trajectory.txt are written atomically at the end (or at an interruption) and
// the streamed files are then removed (remove_streamed_trajectories): they exist only while a run is going or
// after it was killed. trajectory.txt may differ from the streamed SLAM lines: it is the final estimate of
// the whole path (the best particle's history), the streamed line is what the filter knew at that frame.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/pipeline/pipeline_stage.hpp"

namespace glmbslam::app {

inline constexpr const char* kStreamedTrajectoryFile = "trajectory.streaming.txt";
inline constexpr const char* kStreamedVoTrajectoryFile = "vo_trajectory.streaming.txt";

/// A file written one line at a time, each line flushed and synced to the disk.
class StreamedLines {
 public:
  /// Creates (truncates) `path`; throws InputError naming it if that fails.
  explicit StreamedLines(const std::filesystem::path& path);
  /// Appends `line` (with its newline) and syncs it; throws InputError naming the file on a write failure.
  void append(const std::string& line);

 private:
  std::filesystem::path path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
};

class TrajectoryStreamStage : public PipelineStage {
 public:
  explicit TrajectoryStreamStage(const std::filesystem::path& out_dir);
  void on_frame(const FrameOutcome& frame) override;
  void on_finish(RunRecord& record) override;

 private:
  StreamedLines slam_;
  StreamedLines vo_;
};

/// Removes the streamed files of `out_dir` once the final trajectories are written.
void remove_streamed_trajectories(const std::filesystem::path& out_dir);

}  // namespace glmbslam::app
