#pragma once
// Explicitly seeded random streams. Every random draw in the project comes from a RandomStream; a stream is
// identified by (seed, stream id), so e.g. one stream per particle and step gives results independent of the
// thread schedule: the same seed gives the same output whatever the thread count.
#include <cstdint>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace glmbslam {

/// SplitMix64 mixing step: a good 64-bit hash for deriving independent seeds.
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class RandomStream {
 public:
  using Engine = std::mt19937_64;

  explicit RandomStream(std::uint64_t seed, std::uint64_t stream_id = 0)
      : engine_(splitmix64(splitmix64(seed) ^ splitmix64(stream_id + 0x632be59bd9b4e019ULL))) {}

  /// Uniform in [0, 1).
  double uniform() { return std::uniform_real_distribution<double>(0.0, 1.0)(engine_); }
  /// Uniform in [a, b).
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(engine_); }
  /// Standard normal.
  double normal() { return std::normal_distribution<double>(0.0, 1.0)(engine_); }
  /// Normal with mean and standard deviation.
  double normal(double mean, double stddev) { return mean + stddev * normal(); }
  /// Poisson with the given mean (0 for mean ≤ 0).
  int poisson(double mean) { return mean > 0.0 ? std::poisson_distribution<int>(mean)(engine_) : 0; }
  /// Uniform integer in [0, n).
  std::size_t index(std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(engine_); }

  /// Sample from N(mean, cov) using the Cholesky factor of cov (cov must be positive semi-definite;
  /// the LDLT factorisation is used so singular covariances are handled).
  template <int N>
  Eigen::Matrix<double, N, 1> gaussian(const Eigen::Matrix<double, N, 1>& mean,
                                       const Eigen::Matrix<double, N, N>& cov) {
    Eigen::Matrix<double, N, 1> n(mean.rows());
    for (Eigen::Index i = 0; i < mean.rows(); ++i) n(i) = normal();
    const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(cov);
    Eigen::Matrix<double, N, 1> d = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
    Eigen::Matrix<double, N, 1> y = d.cwiseProduct(n);
    Eigen::Matrix<double, N, 1> x = ldlt.matrixL() * y;
    return mean + (ldlt.transpositionsP().transpose() * x);
  }

  Engine& engine() { return engine_; }

 private:
  Engine engine_;
};

}  // namespace glmbslam
