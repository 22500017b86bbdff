#include "sim/default_trajectory.hpp"

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kStraightA = 100.0;  // long sides (130 m block minus the corners)
constexpr double kStraightB = 50.0;   // short sides (80 m block minus the corners)
constexpr double kRadius = 15.0;
constexpr double kRamp = 6.0;  // curvature ramp length at each end of a turn
constexpr double kOverlap = 40.0;
constexpr double kHeightAmplitude = 1.0;
constexpr double kStep = 0.01;  // arc-length integration step

double corner_length() {
  return kRadius * kPi / 2.0 + kRamp;
}  // plateau + 2 ramps, ∫κ ds = π/2

/// Curvature at arc length s (positive: right turn).
double curvature(double s) {
  const double kmax = 1.0 / kRadius;
  const double corner = corner_length();
  const double sides[4] = {kStraightA, kStraightB, kStraightA, kStraightB};
  double start = 0.0;
  for (double side : sides) {
    start += side;
    const double u = s - start;
    if (u >= 0.0 && u < corner) {
      if (u < kRamp) return kmax * u / kRamp;
      if (u > corner - kRamp) return kmax * (corner - u) / kRamp;
      return kmax;
    }
    start += corner;
  }
  return 0.0;
}

}  // namespace

PoseList default_trajectory(double rate_hz, DefaultTrajectoryInfo* info) {
  if (!(rate_hz > 0.0)) throw ConfigError("default trajectory: rate must be positive");
  const double loop = 2.0 * (kStraightA + kStraightB) + 4.0 * corner_length();
  const double total = loop + kOverlap;
  // Integrate the planar path on a fine arc-length grid.
  const auto n = static_cast<std::size_t>(std::ceil(total / kStep)) + 2;
  std::vector<double> xs(n), zs(n), th(n);
  double x = 0.0, z = 0.0, theta = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    xs[i] = x;
    zs[i] = z;
    th[i] = theta;
    const double s = static_cast<double>(i) * kStep;
    const double mid = theta + 0.5 * kStep * curvature(s);
    theta += kStep * curvature(s + 0.5 * kStep);
    x += kStep * std::sin(mid);
    z += kStep * std::cos(mid);
  }
  auto sample = [&](double s, double& px, double& pz, double& pth) {
    const double q = s / kStep;
    const auto i = std::min(static_cast<std::size_t>(q), n - 2);
    const double t = q - static_cast<double>(i);
    px = xs[i] + t * (xs[i + 1] - xs[i]);
    pz = zs[i] + t * (zs[i + 1] - zs[i]);
    pth = th[i] + t * (th[i + 1] - th[i]);
  };
  const double kmax = 1.0 / kRadius;
  auto speed = [&](double s) { return 9.5 - 2.5 * curvature(s) / kmax; };

  PoseList poses;
  const double dt = 1.0 / rate_hz;
  const double h = 1e-3;  // time step of the speed integration
  double s = 0.0, t = 0.0, next = 0.0;
  while (s <= total) {
    if (t >= next - 1e-9) {
      double px, pz, pth;
      sample(s, px, pz, pth);
      const double py = -kHeightAmplitude * std::sin(2.0 * kPi * s / loop);
      const double slope = -kHeightAmplitude * 2.0 * kPi / loop * std::cos(2.0 * kPi * s / loop);
      const double pitch = -std::atan(slope);
      Pose3 T = Pose3::Identity();
      T.linear() = (Eigen::AngleAxisd(pth, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()))
                       .toRotationMatrix();
      T.translation() = Eigen::Vector3d(px, py, pz);
      poses.push_back(T);
      next += dt;
    }
    // Midpoint step of ds/dt = v(s).
    s += h * speed(s + 0.5 * h * speed(s));
    t += h;
  }
  if (info != nullptr) {
    info->loop_length = loop;
    info->total_length = total;
  }
  return io::relative_to_first(poses);
}

}  // namespace glmbslam::sim
