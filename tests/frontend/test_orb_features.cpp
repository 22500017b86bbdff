// ORB internals against exact ground truth: the Hamming distance against a bit-by-bit count, the steered
// BRIEF pattern under an exact 90° image rotation (identical descriptor), the whole extractor's orientation
// and descriptors under that rotation, and stereo matching on a pair with a known sub-pixel disparity.
#include <bitset>
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/random.hpp"
#include "frontend/brief_pattern.hpp"
#include "frontend/orb_extractor.hpp"
#include "frontend/stereo_matcher.hpp"

namespace glmbslam::frontend {
namespace {

// Smoothed random texture with corners at many scales (seeded through a RandomStream).
cv::Mat texture(int rows, int cols, std::uint64_t seed) {
  RandomStream rng(seed);
  cv::Mat coarse(rows / 6 + 1, cols / 6 + 1, CV_8U);
  for (int r = 0; r < coarse.rows; ++r) {
    for (int c = 0; c < coarse.cols; ++c) coarse.at<uchar>(r, c) = static_cast<uchar>(rng.index(256));
  }
  cv::Mat big, fine(rows, cols, CV_8U);
  cv::resize(coarse, big, cv::Size(cols, rows), 0, 0, cv::INTER_NEAREST);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) fine.at<uchar>(r, c) = static_cast<uchar>(rng.index(64));
  }
  cv::Mat img;
  cv::addWeighted(big, 0.75, fine, 1.0, 0.0, img);
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}

TEST(HammingDistance, MatchesBitByBitCount) {
  RandomStream rng(21);
  for (int t = 0; t < 200; ++t) {
    std::uint8_t a[32], b[32];
    int expected = 0;
    for (int i = 0; i < 32; ++i) {
      a[i] = static_cast<std::uint8_t>(rng.index(256));
      b[i] = t % 10 == 0 ? a[i] : static_cast<std::uint8_t>(rng.index(256));
      expected += static_cast<int>(std::bitset<8>(static_cast<unsigned>(a[i] ^ b[i])).count());
    }
    EXPECT_EQ(hamming_distance(a, b), expected);
  }
}

TEST(BriefPattern, PairsInsidePatchAndDeterministic) {
  const BriefPattern p, q;
  ASSERT_EQ(p.pairs().size(), static_cast<std::size_t>(kBriefPairs));
  for (std::size_t i = 0; i < p.pairs().size(); ++i) {
    const auto& a = p.pairs()[i];
    EXPECT_LE(std::hypot(a[0], a[1]), kBriefRadius);
    EXPECT_LE(std::hypot(a[2], a[3]), kBriefRadius);
    EXPECT_EQ(a, q.pairs()[i]);
  }
}

// cv::rotate(…, ROTATE_90_CLOCKWISE) maps pixel (x, y) to (rows − 1 − y, x): offsets turn by +90° in image
// coordinates, exactly the pattern's rotation for an angle of 90°. Both table lookups and the offset table
// must give the descriptor of the unrotated patch at angle 0, bit for bit.
TEST(BriefPattern, ExactQuarterTurnGivesTheSameDescriptor) {
  const cv::Mat img = texture(120, 160, 22);
  cv::Mat rot;
  cv::rotate(img, rot, cv::ROTATE_90_CLOCKWISE);
  const BriefPattern p;
  const std::vector<int> offsets = p.offsets(static_cast<int>(rot.step1()));
  for (int y = 30; y < 90; y += 7) {
    for (int x = 30; x < 130; x += 9) {
      std::uint8_t d0[32], d1[32], d2[32];
      p.describe(img, x, y, 0.0f, d0);
      const int xr = img.rows - 1 - y, yr = x;
      p.describe(rot, xr, yr, 90.0f, d1);
      p.describe(rot.ptr<uchar>(yr) + xr, offsets, 90.0f, d2);
      EXPECT_EQ(hamming_distance(d0, d1), 0) << x << "," << y;
      EXPECT_EQ(hamming_distance(d0, d2), 0) << x << "," << y;
    }
  }
}

// The extractor on an image and on its exact quarter turn: level-0 corners found in both have orientations
// 90° apart and (nearly always) the same descriptor; unrelated corners differ in about half the bits.
TEST(OrbExtractor, OrientationAndDescriptorFollowAQuarterTurn) {
  const cv::Mat img = texture(376, 640, 23);
  cv::Mat rot;
  cv::rotate(img, rot, cv::ROTATE_90_CLOCKWISE);
  OrbConfig config;
  config.features = 1500;
  const OrbExtractor ex(config);
  const OrbFeatures a = ex.extract(img), b = ex.extract(rot);
  ASSERT_GT(a.keypoints.size(), 1000u);
  ASSERT_EQ(a.descriptors.rows, static_cast<int>(a.keypoints.size()));
  int pairs = 0, identical = 0, angle_ok = 0;
  long unrelated_bits = 0;
  int unrelated = 0;
  for (std::size_t i = 0; i < a.keypoints.size(); ++i) {
    const cv::KeyPoint& ka = a.keypoints[i];
    if (ka.octave != 0) continue;
    const cv::Point2f expected(static_cast<float>(img.rows - 1) - ka.pt.y, ka.pt.x);
    for (std::size_t j = 0; j < b.keypoints.size(); ++j) {
      const cv::KeyPoint& kb = b.keypoints[j];
      if (kb.octave != 0 || cv::norm(kb.pt - expected) > 0.01) continue;
      ++pairs;
      const double da = std::fmod(kb.angle - ka.angle + 720.0, 360.0);
      angle_ok += std::abs(da - 90.0) < 0.5;
      identical += hamming_distance(a.descriptors.ptr<uchar>(static_cast<int>(i)),
                                    b.descriptors.ptr<uchar>(static_cast<int>(j))) == 0;
      const std::size_t k = (j * 7919 + 13) % b.keypoints.size();
      if (k != j) {
        unrelated_bits += hamming_distance(a.descriptors.ptr<uchar>(static_cast<int>(i)),
                                           b.descriptors.ptr<uchar>(static_cast<int>(k)));
        ++unrelated;
      }
    }
  }
  ASSERT_GT(pairs, 100);
  EXPECT_GE(angle_ok, pairs * 99 / 100);
  EXPECT_GE(identical, pairs * 9 / 10);  // a 3° orientation bin boundary may separate a few
  ASSERT_GT(unrelated, 0);
  EXPECT_NEAR(static_cast<double>(unrelated_bits) / unrelated, 128.0, 20.0);
}

// A right image that is the left one shifted by a known sub-pixel disparity: every accepted match has that
// disparity to a fraction of a pixel, and most corners find their match.
TEST(StereoMatcher, RecoversKnownSubpixelDisparity) {
  const cv::Mat left = texture(376, 800, 24);
  const double disparity = 17.3;
  const cv::Matx23d shift(1, 0, -disparity, 0, 1, 0);
  cv::Mat right;
  cv::warpAffine(left, right, shift, left.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  OrbConfig orb;
  orb.features = 1500;
  const OrbExtractor ex(orb);
  const OrbFeatures fl = ex.extract(left), fr = ex.extract(right);
  const StereoCamera camera(700.0, 700.0, 400.0, 188.0, 0.5);
  const StereoMatcher matcher(camera, StereoMatchConfig{}, ex.scales());
  const StereoMeasurementList m = matcher.match(fl, fr);
  ASSERT_GT(m.size(), fl.keypoints.size() / 2);
  int close = 0;
  for (const StereoMeasurement& s : m) {
    const double err = s.z.x() - s.z.z() - disparity;
    close += std::abs(err) < 0.25 * s.pixel_sigma / StereoMatchConfig{}.pixel_sigma + 0.25;
    EXPECT_LT(std::abs(err), 1.5 * std::pow(1.2, s.octave)) << "octave " << s.octave;
  }
  EXPECT_GE(close, static_cast<int>(m.size()) * 9 / 10);
}

}  // namespace
}  // namespace glmbslam::frontend
