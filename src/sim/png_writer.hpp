#pragma once
// A fast PNG encoder for the renderer's 8-bit grayscale images: the Sub filter on every row and one deflate
// block with a dynamic Huffman code built for the filtered bytes (no string matching, like zlib's
// Z_HUFFMAN_ONLY strategy, which is what pays on noisy rendered images). About 5× faster than OpenCV/libpng
// at a similar file size; any PNG reader decodes it (tests: cv::imdecode round trip).
#include <cstdint>
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

namespace glmbslam::sim {

/// Reusable buffers of the encoder (one per thread).
struct PngScratch {
  std::vector<std::uint8_t> filtered;
  std::vector<std::uint8_t> encoded;
};

/// Encodes `image` (CV_8UC1, non-empty) into scratch.encoded (the complete PNG file). Throws ConfigError on
/// another image type.
void encode_png_gray8(const cv::Mat& image, PngScratch& scratch);

/// Encodes and writes `image` to `path`. Throws InputError naming the path if it cannot be written.
void write_png_gray8(const std::filesystem::path& path, const cv::Mat& image, PngScratch& scratch);

}  // namespace glmbslam::sim
