#include "app/pipeline/trajectory_stream_stage.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {

StreamedLines::StreamedLines(const std::filesystem::path& path)
    : path_(path), file_(std::fopen(path.string().c_str(), "w"), &std::fclose) {
  if (!file_) throw InputError(path_.string(), std::string("cannot create: ") + std::strerror(errno));
}

void StreamedLines::append(const std::string& line) {
  if (std::fwrite(line.data(), 1, line.size(), file_.get()) != line.size() || std::fflush(file_.get()) != 0 ||
      fdatasync(fileno(file_.get())) != 0) {
    throw InputError(path_.string(), std::string("write failed: ") + std::strerror(errno));
  }
}

TrajectoryStreamStage::TrajectoryStreamStage(const std::filesystem::path& out_dir)
    : slam_(out_dir / kStreamedTrajectoryFile), vo_(out_dir / kStreamedVoTrajectoryFile) {}

void TrajectoryStreamStage::on_frame(const FrameOutcome& frame) {
  vo_.append(io::kitti_pose_line(frame.vo_pose));
  slam_.append(io::kitti_pose_line(frame.filter != nullptr ? frame.filter->pose() : frame.vo_pose));
}

void TrajectoryStreamStage::on_finish(RunRecord& /*record*/) {}

void remove_streamed_trajectories(const std::filesystem::path& out_dir) {
  std::error_code ignored;
  std::filesystem::remove(out_dir / kStreamedTrajectoryFile, ignored);
  std::filesystem::remove(out_dir / kStreamedVoTrajectoryFile, ignored);
}

}  // namespace glmbslam::app
