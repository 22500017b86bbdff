#include "eval/plotly_bundle.hpp"

#include <cstddef>

// GLMBSLAM_PLOTLY_JS is the path of third_party/plotly.js/plotly-gl3d.min.js (src/eval/CMakeLists.txt); the
// assembler copies its bytes into the read-only data of this object file.
#ifndef GLMBSLAM_PLOTLY_JS
#error "GLMBSLAM_PLOTLY_JS must name the vendored plotly.js bundle"
#endif

asm(".section .rodata\n"
    ".balign 16\n"
    "glmbslam_plotly_js_begin:\n"
    ".incbin \"" GLMBSLAM_PLOTLY_JS
    "\"\n"
    "glmbslam_plotly_js_end:\n"
    ".byte 0\n"
    ".previous\n");

extern "C" const char glmbslam_plotly_js_begin[];
extern "C" const char glmbslam_plotly_js_end[];

namespace glmbslam::eval {

std::string_view plotly_bundle() {
  return {glmbslam_plotly_js_begin,
          static_cast<std::size_t>(glmbslam_plotly_js_end - glmbslam_plotly_js_begin)};
}

std::string_view plotly_bundle_version() {
  // The bundle opens with "/**\n* plotly.js (gl3d - minified) v4.1.1\n".
  const std::string_view head = plotly_bundle().substr(0, 200);
  const std::size_t v = head.find(") v");
  if (v == std::string_view::npos) return "unknown";
  const std::size_t begin = v + 3;
  const std::size_t end = head.find_first_of(" \n", begin);
  return head.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin);
}

}  // namespace glmbslam::eval
