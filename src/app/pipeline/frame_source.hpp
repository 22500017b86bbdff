#pragma once
// Stage 1 of the stereo pipeline (reader → frontend): loads the frames of a range in order and runs the
// stereo frontend on them (ORB, stereo matching, triangulation), the next kLookahead frames computed on a
// persistent worker thread (core/worker_thread.hpp: one thread for the whole run, not one per frame) while
// the caller works on the current one. More than one frame ahead, the frames on which the caller is slow (a
// refinement window every few frames) no longer stall the frontend: rendered 07 at N = 10 with --refine ml
// ran at 17.9–18.0 fps one frame ahead, 18.7–21.1 (mean 19.9) three ahead (docs/investigations.md). A frame
// that cannot be read is returned with its error instead of the features: the pipeline bridges it.
#include <cstddef>
#include <deque>
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
  /// Frames computed ahead of the caller (with overlap); each holds one frame's features (a few hundred KiB).
  static constexpr std::size_t kLookahead = 3;

  /// Frames [first, last) of `dataset`; `overlap`: compute frames k+1 … k+kLookahead while the caller handles
  /// frame k.
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
  std::size_t submitted_;                 ///< frames [next_, submitted_) are queued on the worker
  std::unique_ptr<WorkerThread> worker_;  ///< with overlap: computes the frames ahead, in order
  std::deque<std::future<FrameWork>> ahead_;
};

}  // namespace glmbslam::app
