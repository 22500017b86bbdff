#include "io/stereo_dataset.hpp"

namespace glmbslam::io {

StereoFrame StereoDataset::load(std::size_t i) const {
  StereoFrame frame;
  frame.left = load_image(i, StereoSide::kLeft);  // throws InputError if i is out of range
  frame.right = load_image(i, StereoSide::kRight);
  frame.index = i;
  frame.timestamp = timestamps()[i];
  return frame;
}

}  // namespace glmbslam::io
