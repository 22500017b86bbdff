// Texture tile, fast PNG writer and photometric stage of the synthetic stereo renderer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/random.hpp"
#include "sim/pixel_noise.hpp"
#include "sim/png_writer.hpp"
#include "sim/render_texture.hpp"
#include "sim/texture_tile.hpp"

namespace glmbslam::sim {
namespace {

using texture::MipTile;

TEST(MipTile, LevelZeroHoldsThePatternAndMipsAreBoxAverages) {
  const MipTile& tile = MipTile::mondrian();
  const double texel = 1.0 / MipTile::kTexelsPerUnit;
  // Level 0: the quantised pattern at texel centres (brute-force evaluation).
  RandomStream rng(3, 0);
  for (int k = 0; k < 2000; ++k) {
    const int i = static_cast<int>(rng.index(MipTile::kSize));
    const int j = static_cast<int>(rng.index(MipTile::kSize));
    const float v = MipTile::pattern((i + 0.5) * texel, (j + 0.5) * texel, texel);
    const float decoded = MipTile::kDecodeScale * tile.texel(0, i, j) + MipTile::kDecodeOffset;
    EXPECT_NEAR(decoded, std::clamp(v, -2.0f, 2.0f), 0.5f * MipTile::kDecodeScale + 1e-6f);
  }
  // Level l: within quantisation of the mean of its 2×2 children.
  for (int l = 1; l < MipTile::kLevels; ++l) {
    const int n = MipTile::kSize >> l;
    for (int k = 0; k < 200; ++k) {
      const int i = static_cast<int>(rng.index(static_cast<std::size_t>(n)));
      const int j = static_cast<int>(rng.index(static_cast<std::size_t>(n)));
      const double mean =
          0.25 * (tile.texel(l - 1, 2 * i, 2 * j) + tile.texel(l - 1, 2 * i + 1, 2 * j) +
                  tile.texel(l - 1, 2 * i, 2 * j + 1) + tile.texel(l - 1, 2 * i + 1, 2 * j + 1));
      EXPECT_NEAR(tile.texel(l, i, j), mean, 1.01) << "level " << l;
    }
  }
}

TEST(MipTile, PatternIsPeriodicAndRichInEdges) {
  // Seamless wrap: the pattern repeats with the tile period.
  const double period = static_cast<double>(MipTile::kSize) / MipTile::kTexelsPerUnit;
  RandomStream rng(4, 0);
  int edges = 0;
  for (int k = 0; k < 1000; ++k) {
    const double x = rng.uniform(-100.0, 100.0), y = rng.uniform(-100.0, 100.0);
    EXPECT_NEAR(MipTile::pattern(x, y, 0.01), MipTile::pattern(x + period, y - 2 * period, 0.01), 1e-4);
    if (std::abs(MipTile::pattern(x, y, 0.001) - MipTile::pattern(x + 0.05, y, 0.001)) > 0.3) ++edges;
  }
  EXPECT_GT(edges, 150);  // a step of 5 % of a pattern unit often crosses a rectangle edge
}

TEST(MipTile, SampleAtTexelCentresAndSpanEqualsScalar) {
  const MipTile& tile = MipTile::mondrian();
  // At a texel centre of level l (lod exactly l) the sample is the stored texel.
  for (int l = 0; l + 1 < MipTile::kLevels; ++l) {
    for (int i : {0, 5, (MipTile::kSize >> l) - 1}) {
      if (i >= (MipTile::kSize >> l)) continue;
      const int j = i / 2;
      const float u = (static_cast<float>(i) + 0.5f) * static_cast<float>(1 << l);
      const float v = (static_cast<float>(j) + 0.5f) * static_cast<float>(1 << l);
      EXPECT_FLOAT_EQ(tile.sample(MipTile::to_fixed(u), MipTile::to_fixed(v), static_cast<float>(l)),
                      tile.texel(l, i, j));
      // Wrapping: one period away (also negative) gives the same value.
      const float p = static_cast<float>(MipTile::kSize);
      EXPECT_FLOAT_EQ(
          tile.sample(MipTile::to_fixed(u - 3 * p), MipTile::to_fixed(v + p), static_cast<float>(l)),
          tile.texel(l, i, j));
    }
  }
  // The four-at-a-time span sampler is bit-identical to the scalar sampler.
  RandomStream rng(5, 0);
  const int n = 1003;
  std::vector<std::int32_t> U(n), V(n);
  std::vector<float> lod(n), out(n);
  for (int k = 0; k < n; ++k) {
    U[static_cast<std::size_t>(k)] = MipTile::to_fixed(static_cast<float>(rng.uniform(-1e5, 1e5)));
    V[static_cast<std::size_t>(k)] = MipTile::to_fixed(static_cast<float>(rng.uniform(-1e5, 1e5)));
    lod[static_cast<std::size_t>(k)] = static_cast<float>(rng.uniform(-2.0, 14.0));
  }
  tile.sample_span(U.data(), V.data(), lod.data(), n, out.data());
  for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
    EXPECT_EQ(out[k], tile.sample(U[k], V[k], lod[k])) << k;
    EXPECT_GE(out[k], 0.0f);
    EXPECT_LE(out[k], 255.0f);
  }
  // The baseline (SSE2) path gives the same bits as the run-time chosen one (AVX2 on most CPUs), also for
  // the highest levels (the gathers read the last texels of the tile) and for every span length mod 8.
  for (int k = 0; k < n; k += 7) lod[static_cast<std::size_t>(k)] = 11.0f + static_cast<float>(k % 3);
  tile.sample_span(U.data(), V.data(), lod.data(), n, out.data());
  for (int len : {1, 3, 4, 7, 8, 9, 15, 16, 17, n}) {
    std::vector<float> base(static_cast<std::size_t>(len));
    tile.sample_span_baseline(U.data(), V.data(), lod.data(), len, base.data());
    for (std::size_t k = 0; k < static_cast<std::size_t>(len); ++k)
      ASSERT_EQ(base[k], out[k]) << len << " " << k;
  }
  RecordProperty("avx2", MipTile::avx2_enabled() ? "yes" : "no");
}

TEST(PngWriter, RoundTripsThroughOpenCv) {
  RandomStream rng(6, 0);
  for (const auto& size : {cv::Size(1241, 376), cv::Size(1, 1), cv::Size(7, 3)}) {
    for (int pattern = 0; pattern < 3; ++pattern) {
      cv::Mat image(size, CV_8UC1);
      for (int r = 0; r < image.rows; ++r) {
        for (int c = 0; c < image.cols; ++c) {
          const int noise = static_cast<int>(rng.normal() * 3.0);
          const int v = pattern == 0   ? 100
                        : pattern == 1 ? (c / 40 + r / 30) * 37 + noise
                                       : static_cast<int>(rng.index(256));
          image.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
        }
      }
      PngScratch scratch;
      encode_png_gray8(image, scratch);
      const cv::Mat back = cv::imdecode(scratch.encoded, cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(back.empty()) << size << " pattern " << pattern;
      ASSERT_EQ(back.type(), CV_8UC1);
      EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0) << size << " pattern " << pattern;
      if (size.width == 1241 && pattern == 1) {
        // Smooth blocks plus noise of σ = 3 grey levels compress well below 8 bits per pixel.
        EXPECT_LT(scratch.encoded.size(), image.total() * 6 / 10);
      }
    }
  }
}

TEST(PixelNoise, HasTheRequestedStandardDeviationAndNoBias) {
  const int width = 1241;
  std::vector<float> albedo(1244, 0.5f), vig(1244, 0.0f);
  std::vector<std::uint8_t> row(static_cast<std::size_t>(width));
  PixelNoise noise(123, 456, 4.0f);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int r = 0; r < 200; ++r) {
    noise.apply_row(albedo.data(), vig.data(), 200.0f, 1.0f, width, row.data());
    for (std::uint8_t v : row) {
      const double e = v - 100.0;
      sum += e;
      sum2 += e * e;
      ++n;
    }
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 0.05);
  EXPECT_NEAR(std::sqrt(sum2 / n - mean * mean), std::sqrt(16.0 + 1.0 / 12.0), 0.05);  // σ² + rounding
  // Without noise: exact rounding of the gain·albedo·vignetting product.
  PixelNoise clean(1, 2, 0.0f);
  clean.apply_row(albedo.data(), vig.data(), 201.0f, 0.9f, width, row.data());
  for (std::uint8_t v : row) EXPECT_EQ(v, 90);  // 201·0.5·0.9 = 90.45
}

}  // namespace
}  // namespace glmbslam::sim
