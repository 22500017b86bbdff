#include "io/stereo_dataset.hpp"

#include <string>

#include "core/error.hpp"

namespace glmbslam::io {

StereoFrame StereoDataset::load(std::size_t i) const {
  if (i >= size())
    throw InputError(name(),
                     "frame " + std::to_string(i) + " out of range (" + std::to_string(size()) + " frames)");
  StereoFrame frame;
  frame.index = i;
  frame.timestamp = timestamps()[i];
  frame.left = load_image(i, StereoSide::kLeft);
  frame.right = load_image(i, StereoSide::kRight);
  return frame;
}

}  // namespace glmbslam::io
