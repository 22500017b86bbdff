#pragma once
// Stage 1 of the stereo pipeline (reader → frontend): loads the frames of a range in order and runs the
// stereo frontend on them (ORB, stereo matching, triangulation), the next frame computed on a persistent
// worker thread (core/worker_thread.hpp: one thread for the whole run, not one per frame) while the caller
// works on the current one. A frame that cannot be read is returned with its error instead of the features:
// the pipeline bridges it.
#include <cstddef>
#include <future>
#include <memory>
#include <string>

#include "core/worker_thread.hpp"
#include "frontend/stereo_frontend.hpp"
#include "io/stereo_dataset.hpp"

namespace glmbslam::app {

/// The frontend's output for one frame.
struct FrameWork {
  std::size_t index = 0;   ///< frame index in the dataset
  double timestamp = 0.0;  ///< seconds (the dataset's timestamps)
  bool loaded = false;     ///< false: the images could not be read (load_error says why)
  std::string load_error;
  frontend::StereoFrameFeatures features;
  double frontend_ms = 0.0;  ///< load + frontend wall time
};

class FrameSource {
 public:
  /// Frames [first, last) of `dataset`; `overlap`: compute frame k+1 while the caller handles frame k.
  FrameSource(const io::StereoDataset& dataset, const frontend::StereoFrontend& frontend, std::size_t first,
              std::size_t last, bool overlap);
  ~FrameSource();
  FrameSource(const FrameSource&) = delete;
  FrameSource& operator=(const FrameSource&) = delete;

  bool done() const { return next_ >= last_; }
  /// The next frame's features (blocks until they are computed). Precondition: !done().
  FrameWork next();

 private:
  FrameWork process(std::size_t index) const;

  const io::StereoDataset& dataset_;
  const frontend::StereoFrontend& frontend_;
  std::size_t next_, last_;
  std::unique_ptr<WorkerThread> worker_;  ///< with overlap: computes the frame ahead
  std::future<FrameWork> ahead_;
};

}  // namespace glmbslam::app
