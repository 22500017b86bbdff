#include "frontend/brief_pattern.hpp"

#include <cmath>

#include "core/random.hpp"

namespace glmbslam::frontend {

namespace {

// Deterministic standard normal pairs (Box–Muller on a SplitMix64 counter sequence): the pattern must not
// depend on the standard library's distribution implementations.
class PatternNormals {
 public:
  double next() {
    if (have_spare_) {
      have_spare_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(splitmix64(counter_++) >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = (static_cast<double>(splitmix64(counter_++) >> 11) + 0.5) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    have_spare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::uint64_t counter_ = 0x0b21efull;
  double spare_ = 0.0;
  bool have_spare_ = false;
};

}  // namespace

BriefPattern::BriefPattern() {
  PatternNormals normals;
  const double sigma = 31.0 / 5.0;  // BRIEF G II: σ² = S² / 25 for the patch size S
  const double r2 = static_cast<double>(kBriefRadius) * kBriefRadius;
  pairs_.reserve(kBriefPairs);
  while (static_cast<int>(pairs_.size()) < kBriefPairs) {
    std::array<float, 4> p;
    bool inside = true;
    for (int k = 0; k < 4; k += 2) {
      const double x = sigma * normals.next(), y = sigma * normals.next();
      inside = inside && x * x + y * y <= r2;
      p[static_cast<std::size_t>(k)] = static_cast<float>(x);
      p[static_cast<std::size_t>(k + 1)] = static_cast<float>(y);
    }
    const double dx = p[0] - p[2], dy = p[1] - p[3];
    if (!inside || dx * dx + dy * dy < 4.0) continue;  // both points in the disc, at least 2 px apart
    pairs_.push_back(p);
  }
  rotated_.resize(kBriefAngleBins);
  for (int b = 0; b < kBriefAngleBins; ++b) {
    const double a = 2.0 * M_PI * b / kBriefAngleBins, c = std::cos(a), s = std::sin(a);
    auto& table = rotated_[static_cast<std::size_t>(b)];
    for (int i = 0; i < kBriefPairs; ++i) {
      const auto& p = pairs_[static_cast<std::size_t>(i)];
      for (int k = 0; k < 2; ++k) {  // image coordinates (x right, y down), rotation by +a
        const double x = p[static_cast<std::size_t>(2 * k)], y = p[static_cast<std::size_t>(2 * k + 1)];
        table[static_cast<std::size_t>(4 * i + 2 * k)] = static_cast<std::int8_t>(std::lround(c * x - s * y));
        table[static_cast<std::size_t>(4 * i + 2 * k + 1)] =
            static_cast<std::int8_t>(std::lround(s * x + c * y));
      }
    }
  }
}

namespace {

int angle_bin(float angle_deg) {
  int bin = static_cast<int>(std::lround(angle_deg * (kBriefAngleBins / 360.0f)));
  bin %= kBriefAngleBins;
  return bin < 0 ? bin + kBriefAngleBins : bin;
}

}  // namespace

std::vector<int> BriefPattern::offsets(int step) const {
  std::vector<int> o(static_cast<std::size_t>(kBriefAngleBins) * 2 * kBriefPairs);
  for (int b = 0; b < kBriefAngleBins; ++b) {
    const std::int8_t* t = rotated_[static_cast<std::size_t>(b)].data();
    int* ob = o.data() + static_cast<std::size_t>(b) * 2 * kBriefPairs;
    for (int i = 0; i < 2 * kBriefPairs; ++i) ob[i] = t[2 * i + 1] * step + t[2 * i];
  }
  return o;
}

void BriefPattern::describe(const std::uint8_t* c, const std::vector<int>& offsets, float angle_deg,
                            std::uint8_t* out) const {
  const int* o = offsets.data() + static_cast<std::size_t>(angle_bin(angle_deg)) * 2 * kBriefPairs;
  for (int byte = 0; byte < kBriefPairs / 8; ++byte, o += 16) {
    int v = 0;
    for (int bit = 0; bit < 8; ++bit) v |= (c[o[2 * bit]] < c[o[2 * bit + 1]]) << bit;
    out[byte] = static_cast<std::uint8_t>(v);
  }
}

void BriefPattern::describe(const cv::Mat& smoothed, int x, int y, float angle_deg, std::uint8_t* out) const {
  const int bin = angle_bin(angle_deg);
  const std::int8_t* t = rotated_[static_cast<std::size_t>(bin)].data();
  const int step = static_cast<int>(smoothed.step1());
  const std::uint8_t* c = smoothed.ptr<std::uint8_t>(y) + x;
  for (int byte = 0; byte < kBriefPairs / 8; ++byte) {
    int v = 0;
    for (int bit = 0; bit < 8; ++bit, t += 4) {
      v |= (c[t[1] * step + t[0]] < c[t[3] * step + t[2]]) << bit;
    }
    out[byte] = static_cast<std::uint8_t>(v);
  }
}

}  // namespace glmbslam::frontend
