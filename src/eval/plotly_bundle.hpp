#pragma once
// The vendored plotly.js bundle (third_party/plotly.js), compiled into the executable so every report.html
// can inline it and open offline without any file installed next to the binary.
#include <string_view>

namespace glmbslam::eval {

/// The minified plotly.js gl3d bundle, byte for byte as vendored.
std::string_view plotly_bundle();

/// Its version, as recorded in third_party/plotly.js/README.md.
std::string_view plotly_bundle_version();

}  // namespace glmbslam::eval
