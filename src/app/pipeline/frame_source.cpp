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
      submitted_(first),
      worker_(overlap ? std::make_unique<WorkerThread>() : nullptr) {}

FrameSource::~FrameSource() {
  for (auto& f : ahead_) f.wait();  // never leave a worker reading through a dangling reference
}

FrameWork FrameSource::process(std::size_t index) const {
  FrameWork w;
  w.index = index;
  const auto& times = dataset_.timestamps();
  w.timestamp = index < times.size() ? times[index] : std::nan("");
  Stopwatch watch;
  try {
    // each image decoded on the thread that extracts its features (the two sides in parallel)
    w.features = frontend_.process([&] { return dataset_.load_image(index, io::StereoSide::kLeft); },
                                   [&] { return dataset_.load_image(index, io::StereoSide::kRight); });
    w.loaded = true;
  } catch (const InputError& e) {
    w.load_error = e.what();
  }
  w.frontend_ms = watch.elapsed_ms();
  return w;
}

FrameWork FrameSource::next() {
  const std::size_t index = next_++;
  FrameWork work;
  if (ahead_.empty()) {  // the first frame (or no overlap): computed here
    work = process(index);
    submitted_ = next_;
  } else {
    work = ahead_.front().get();
    ahead_.pop_front();
  }
  for (; worker_ && submitted_ < last_ && submitted_ < next_ + kLookahead; ++submitted_)
    ahead_.push_back(worker_->submit([this, i = submitted_] { return process(i); }));
  return work;
}

}  // namespace glmbslam::app
