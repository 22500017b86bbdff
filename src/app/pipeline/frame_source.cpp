#include "app/pipeline/frame_source.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::app {

FrameSource::FrameSource(const io::StereoDataset& dataset, const frontend::StereoFrontend& frontend,
                         std::size_t first, std::size_t last, bool overlap)
    : dataset_(dataset),
      frontend_(frontend),
      next_(first),
      last_(last),
      worker_(overlap ? std::make_unique<WorkerThread>() : nullptr) {}

FrameSource::~FrameSource() {
  if (ahead_.valid()) ahead_.wait();  // never leave a worker reading through a dangling reference
}

FrameWork FrameSource::process(std::size_t index) const {
  FrameWork w;
  w.index = index;
  const auto& times = dataset_.timestamps();
  w.timestamp = index < times.size() ? times[index] : std::nan("");
  Stopwatch watch;
  try {
    const io::StereoFrame frame = dataset_.load(index);
    w.features = frontend_.process(frame.left, frame.right);
    w.loaded = true;
  } catch (const InputError& e) {
    w.load_error = e.what();
  }
  w.frontend_ms = watch.elapsed_ms();
  return w;
}

FrameWork FrameSource::next() {
  const std::size_t index = next_++;
  FrameWork work = ahead_.valid() ? ahead_.get() : process(index);
  if (worker_ && next_ < last_) {
    ahead_ = worker_->submit([this, i = next_] { return process(i); });
  }
  return work;
}

}  // namespace glmbslam::app
