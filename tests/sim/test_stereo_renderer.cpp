// Geometry of the synthetic stereo renderer: projections, disparities and depth are exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/default_trajectory.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "sim/stereo_procedural_world.hpp"
#include "sim/stereo_renderer.hpp"

namespace glmbslam::sim {
namespace {

RenderOptions clean_options() {
  RenderOptions o;
  o.photometric.noise_sigma = 0.0;
  o.photometric.vignetting = 0.0;
  o.photometric.exposure_sigma = 0.0;
  return o;
}

Eigen::Vector2d project(const StereoCalibration& c, const Pose3& T_world_cam,
                        const Eigen::Vector3d& p_world) {
  const Eigen::Vector3d p = T_world_cam.inverse() * p_world;
  return {c.fx * p.x() / p.z() + c.cx, c.fy * p.y() / p.z() + c.cy};
}

/// A 1 m square marker quad centred at `centre` facing the camera direction `normal`, with a bright disc
/// (radius 0.12 m) at its centre on a dark background.
Surface marker(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d u = n.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d v = n.cross(u).normalized();
  Surface s = make_quad(centre - 0.5 * u - 0.5 * v, centre + 0.5 * u - 0.5 * v, centre + 0.5 * u + 0.5 * v,
                        centre - 0.5 * u + 0.5 * v, TextureKind::kDisc, 1, 0.1f, 0.8f);
  s.origin = centre;
  s.param0 = 0.12f;
  return s;
}

/// Intensity-weighted centroid of (I − background) in a window around `guess`.
Eigen::Vector2d centroid(const cv::Mat& image, const Eigen::Vector2d& guess, int radius, double background) {
  double sw = 0.0, su = 0.0, sv = 0.0;
  const int u0 = static_cast<int>(std::lround(guess.x())), v0 = static_cast<int>(std::lround(guess.y()));
  for (int v = v0 - radius; v <= v0 + radius; ++v) {
    for (int u = u0 - radius; u <= u0 + radius; ++u) {
      const double w = std::max(0.0, image.at<std::uint8_t>(v, u) - background);
      sw += w;
      su += w * u;
      sv += w * v;
    }
  }
  return {su / sw, sv / sw};
}

/// Brute-force image centroid of the projected disc (radius r, centre c, in-plane axes u, v): the disc is cut
/// into small polar cells whose projected quadrilaterals are summed (area-weighted centroids). For a tilted
/// disc this differs from the projection of its centre by a few hundredths of a pixel (perspective).
Eigen::Vector2d projected_disc_centroid(const StereoCalibration& calib, const Pose3& T_world_cam,
                                        const Surface& s, double r) {
  const int nr = 80, nphi = 160;
  double area = 0.0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  auto point = [&](double rho, double phi) {
    return project(calib, T_world_cam,
                   s.origin + rho * (std::cos(phi) * s.axis_u + std::sin(phi) * s.axis_v));
  };
  for (int i = 0; i < nr; ++i) {
    for (int j = 0; j < nphi; ++j) {
      const double r0 = r * i / nr, r1 = r * (i + 1) / nr;
      const double p0 = 2.0 * M_PI * j / nphi, p1 = 2.0 * M_PI * (j + 1) / nphi;
      const Eigen::Vector2d q[4] = {point(r0, p0), point(r1, p0), point(r1, p1), point(r0, p1)};
      // Polygon area and centroid (shoelace).
      double a = 0.0;
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d& x0 = q[k];
        const Eigen::Vector2d& x1 = q[(k + 1) % 4];
        const double cross = x0.x() * x1.y() - x1.x() * x0.y();
        a += cross;
        c += cross * (x0 + x1);
      }
      if (std::abs(a) < 1e-15) continue;
      area += 0.5 * a;
      sum += c / 6.0;
    }
  }
  return sum / area;
}

TEST(StereoRenderer, MarkerAppearsAtItsPinholeProjection) {
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  // A rotated, translated camera.
  Pose3 T_world_cam = Pose3::Identity();
  T_world_cam.linear() =
      (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(-0.05, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  T_world_cam.translation() = Eigen::Vector3d(3.0, -1.0, 20.0);
  // Markers at several image positions and depths, each slightly tilted.
  const std::vector<Eigen::Vector3d> cam_points = {{0.0, 0.0, 8.0},   {-3.5, -0.8, 7.0}, {4.0, 1.0, 9.0},
                                                   {-6.0, 1.2, 15.0}, {7.0, -1.5, 12.0}, {1.5, 0.9, 5.5}};
  SurfaceList surfaces;
  std::vector<Eigen::Vector3d> world_points;
  for (std::size_t i = 0; i < cam_points.size(); ++i) {
    const Eigen::Vector3d pw = T_world_cam * cam_points[i];
    const Eigen::Vector3d towards = T_world_cam.translation() - pw;
    const Eigen::Vector3d tilt = T_world_cam.linear() * Eigen::Vector3d(0.15 * std::cos(i), 0.1, 0.0);
    surfaces.push_back(marker(pw, towards.normalized() + tilt));
    world_points.push_back(pw);
  }
  const SurfaceListWorld world(surfaces);
  StereoRenderer renderer(world, calib, clean_options());
  RenderedFrame frame;
  renderer.render(T_world_cam, 0.0, 0, frame);
  Pose3 T_world_right = T_world_cam;
  T_world_right.translation() += T_world_cam.linear() * Eigen::Vector3d(calib.baseline, 0, 0);
  for (std::size_t i = 0; i < world_points.size(); ++i) {
    const Eigen::Vector2d centre_l = project(calib, T_world_cam, world_points[i]);
    const Eigen::Vector2d centre_r = project(calib, T_world_right, world_points[i]);
    const Eigen::Vector2d expected_l = projected_disc_centroid(calib, T_world_cam, surfaces[i], 0.12);
    const Eigen::Vector2d expected_r = projected_disc_centroid(calib, T_world_right, surfaces[i], 0.12);
    // The perspective shift of the centroid is small: the disc centre itself is within 0.3 px.
    EXPECT_LT((expected_l - centre_l).norm(), 0.3);
    EXPECT_LT((expected_r - centre_r).norm(), 0.3);
    // Window inside the 1 m marker quad: radius 0.3 m projected.
    const int radius = static_cast<int>(0.3 * calib.fx / cam_points[i].z());
    const Eigen::Vector2d got_l = centroid(frame.left, centre_l, radius, 255.0 * 0.1);
    const Eigen::Vector2d got_r = centroid(frame.right, centre_r, radius, 255.0 * 0.1);
    EXPECT_LT((got_l - expected_l).norm(), 0.05)
        << "marker " << i << " left " << got_l.transpose() << " vs " << expected_l.transpose();
    EXPECT_LT((got_r - expected_r).norm(), 0.05)
        << "marker " << i << " right " << got_r.transpose() << " vs " << expected_r.transpose();
    // Exact depth at the marker centre pixel (plane depth at that pixel).
    const int u = static_cast<int>(std::lround(expected_l.x())),
              v = static_cast<int>(std::lround(expected_l.y()));
    EXPECT_NEAR(frame.depth.at<float>(v, u), (T_world_cam.inverse() * world_points[i]).z(), 0.05);
  }
}

/// Sub-pixel disparity of a block (SSD over integer shifts, parabola through the minimum).
double block_disparity(const cv::Mat& left, const cv::Mat& right, int u0, int v0, int half, int dmin,
                       int dmax) {
  std::vector<double> cost;
  for (int d = dmin; d <= dmax; ++d) {
    double c = 0.0;
    for (int v = v0 - half; v <= v0 + half; ++v) {
      for (int u = u0 - half; u <= u0 + half; ++u) {
        const double e = static_cast<double>(left.at<std::uint8_t>(v, u)) - right.at<std::uint8_t>(v, u - d);
        c += e * e;
      }
    }
    cost.push_back(c);
  }
  const auto best = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
  if (best == 0 || best + 1 == static_cast<int>(cost.size())) return dmin + best;
  const double a = cost[static_cast<std::size_t>(best - 1)], b = cost[static_cast<std::size_t>(best)],
               c = cost[static_cast<std::size_t>(best + 1)];
  return dmin + best + 0.5 * (a - c) / (a - 2.0 * b + c);
}

TEST(StereoRenderer, FrontoParallelDisparityIsFxBOverZ) {
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  for (const double Z : {6.0, 10.0, 25.0}) {
    SurfaceList surfaces;
    Surface wall = make_quad({-60, -30, Z}, {60, -30, Z}, {60, 30, Z}, {-60, 30, Z}, TextureKind::kMondrian,
                             7, 0.5f, 0.45f);
    wall.param0 = 1.0f * static_cast<float>(Z / 10.0);
    surfaces.push_back(wall);
    const SurfaceListWorld world(surfaces);
    StereoRenderer renderer(world, calib, clean_options());
    RenderedFrame frame;
    renderer.render(Pose3::Identity(), 0.0, 0, frame);
    const double expected = calib.fx * calib.baseline / Z;
    const int dmin = static_cast<int>(expected) - 6, dmax = static_cast<int>(expected) + 6;
    int blocks = 0;
    for (int v = 60; v <= 320; v += 40) {
      for (int u = 200; u <= 1150; u += 60) {
        const double d = block_disparity(frame.left, frame.right, u, v, 10, dmin, dmax);
        EXPECT_NEAR(d, expected, 0.25) << "Z " << Z << " block (" << u << ", " << v << ")";
        ++blocks;
      }
    }
    EXPECT_GT(blocks, 50);
    // Depth is exactly Z on the fronto-parallel wall.
    for (int v = 0; v < calib.height; v += 37) {
      for (int u = 0; u < calib.width; u += 53) EXPECT_NEAR(frame.depth.at<float>(v, u), Z, 1e-4 * Z);
    }
  }
}

TEST(StereoRenderer, ProceduralDepthIsConsistentWithTheRightImage) {
  // Exact ground truth in a full street scene: every left pixel with depth z reappears in the right image at
  // u − fx·b/z (rectified), except at occlusions and object borders. On textured pixels the photometric error
  // at that disparity must be clearly smaller than half a pixel off on either side.
  const PoseList trajectory = default_trajectory();
  ProceduralWorldOptions wopt;
  wopt.seed = 3;
  const ProceduralWorld world(trajectory, wopt);
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  StereoRenderer renderer(world, calib, clean_options());
  RenderedFrame frame;
  renderer.render(trajectory[40], 4.0, 40, frame);
  auto sample_right = [&](int v, double ur) {
    const int i = static_cast<int>(std::floor(ur));
    const double t = ur - i;
    return (1 - t) * frame.right.at<std::uint8_t>(v, i) + t * frame.right.at<std::uint8_t>(v, i + 1);
  };
  double e_minus = 0.0, e_true = 0.0, e_plus = 0.0;
  int n = 0;
  for (int v = 5; v < calib.height - 5; v += 2) {
    for (int u = 60; u < calib.width - 5; u += 2) {
      const float z = frame.depth.at<float>(v, u);
      if (z <= 0.0f) continue;
      if (std::abs(frame.left.at<std::uint8_t>(v, u + 1) - frame.left.at<std::uint8_t>(v, u - 1)) < 12)
        continue;
      const double ur = u - calib.fx * calib.baseline / z;
      if (ur < 2.0 || ur > calib.width - 3.0) continue;
      const double l = frame.left.at<std::uint8_t>(v, u);
      e_minus += std::abs(sample_right(v, ur - 0.5) - l);
      e_true += std::abs(sample_right(v, ur) - l);
      e_plus += std::abs(sample_right(v, ur + 0.5) - l);
      ++n;
    }
  }
  ASSERT_GT(n, 5000);
  std::printf(
      "mean |I_L - I_R| on %d textured pixels: %.2f at the true disparity, %.2f / %.2f half a pixel off\n", n,
      e_true / n, e_minus / n, e_plus / n);
  EXPECT_LT(e_true, 0.6 * std::min(e_minus, e_plus));
}

TEST(StereoRenderer, CameraStaysAboveTheGroundAndRoadIsFree) {
  const PoseList trajectory = default_trajectory();
  const ProceduralWorld world(trajectory, {});
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  StereoRenderer renderer(world, calib, clean_options());
  RenderedFrame frame;
  for (std::size_t i = 0; i < trajectory.size(); i += 97) {
    const Eigen::Vector3d p = trajectory[i].translation();
    EXPECT_NEAR(world.ground_height(p.x(), p.z()) - p.y(), 1.65, 0.1) << "frame " << i;
    renderer.render(trajectory[i], 0.1 * static_cast<double>(i), i, frame);
    // The road straight ahead is free: the pixel column at cx in the lower part sees the ground within 10 m.
    const int u = static_cast<int>(calib.cx);
    const int v = calib.height - 10;
    const double ray_y = (v - calib.cy) / calib.fy;
    const double z = frame.depth.at<float>(v, u);
    EXPECT_NEAR(z * ray_y, 1.65, 0.15) << "frame " << i << ": no ground straight ahead (depth " << z << ")";
  }
}

TEST(ProceduralWorld, PrecomputedCachesGiveTheSameSurfacesAsPerFrameGeneration) {
  // The station grid array and the station/tower caches only change how the surfaces are found: the list
  // (every corner, axis, texture parameter, and the order) is the same as generating everything per frame,
  // also away from the path (cells outside the cached boxes) and with movers.
  const PoseList trajectory = default_trajectory();
  ProceduralWorldOptions cached_options;
  cached_options.movers = 3;
  ProceduralWorldOptions plain_options = cached_options;
  plain_options.precompute = false;
  const ProceduralWorld cached(trajectory, cached_options);
  const ProceduralWorld plain(trajectory, plain_options);
  SurfaceList a, b;
  std::vector<Eigen::Vector3d> positions;
  for (std::size_t i = 0; i < trajectory.size(); i += 61) positions.push_back(trajectory[i].translation());
  positions.emplace_back(2500.0, -1.0, -1800.0);  // far outside the path's box
  std::size_t total = 0;
  for (std::size_t q = 0; q < positions.size(); ++q) {
    const double time = 0.1 * static_cast<double>(q);
    cached.collect(positions[q], time, a);
    plain.collect(positions[q], time, b);
    ASSERT_EQ(a.size(), b.size()) << q;
    total += a.size();
    for (std::size_t k = 0; k < a.size(); ++k) {
      for (std::size_t c = 0; c < 4; ++c) ASSERT_EQ(a[k].corners[c], b[k].corners[c]) << q << " " << k;
      ASSERT_EQ(a[k].corner_count, b[k].corner_count);
      ASSERT_EQ(a[k].origin, b[k].origin);
      ASSERT_EQ(a[k].axis_u, b[k].axis_u);
      ASSERT_EQ(a[k].axis_v, b[k].axis_v);
      ASSERT_EQ(a[k].normal, b[k].normal);
      ASSERT_EQ(a[k].two_sided, b[k].two_sided);
      ASSERT_EQ(a[k].kind, b[k].kind);
      ASSERT_EQ(a[k].seed, b[k].seed);
      ASSERT_EQ(a[k].albedo, b[k].albedo);
      ASSERT_EQ(a[k].contrast, b[k].contrast);
      ASSERT_EQ(a[k].param0, b[k].param0);
      ASSERT_EQ(a[k].param1, b[k].param1);
    }
  }
  EXPECT_GT(total, 1000u);  // the comparison covered real scenes
}

TEST(StereoRenderer, SameSeedSameImagesDifferentSeedDifferentImages) {
  const PoseList trajectory = default_trajectory();
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  auto render = [&](std::uint64_t seed, int movers) {
    ProceduralWorldOptions wopt;
    wopt.seed = seed;
    wopt.movers = movers;
    const ProceduralWorld world(trajectory, wopt);
    RenderOptions ropt;
    ropt.seed = seed;
    StereoRenderer renderer(world, calib, ropt);
    RenderedFrame f;
    renderer.render(trajectory[123], 12.3, 123, f);
    return f;
  };
  const RenderedFrame a = render(5, 3), b = render(5, 3), c = render(6, 3);
  EXPECT_EQ(cv::norm(a.left, b.left, cv::NORM_L1), 0.0);
  EXPECT_EQ(cv::norm(a.right, b.right, cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(a.left, c.left, cv::NORM_L1), 1e5);
}

// render --right-gain: the right image alone scales (up to grey-level rounding and saturation), the left one
// and the noise streams stay as they were.
TEST(StereoRenderer, RightGainScalesTheRightImageOnly) {
  const PoseList trajectory = default_trajectory();
  const ProceduralWorld world(trajectory, {});
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  auto render = [&](double right_gain) {
    RenderOptions ropt;
    ropt.photometric = PhotometricOptions{0.0, 0.2, 0.0, right_gain};
    StereoRenderer renderer(world, calib, ropt);
    RenderedFrame f;
    renderer.render(trajectory[200], 20.0, 200, f);
    return f;
  };
  const RenderedFrame one = render(1.0), dim = render(0.7);
  EXPECT_EQ(cv::norm(one.left, dim.left, cv::NORM_L1), 0.0);
  cv::Mat expected;
  one.right.convertTo(expected, CV_32F, 0.7);
  cv::Mat got;
  dim.right.convertTo(got, CV_32F);
  cv::Mat unsaturated = one.right < 255;
  EXPECT_LE(cv::norm(expected, got, cv::NORM_INF, unsaturated), 1.0);  // each rounded to a grey level
}

TEST(StereoRenderer, ImagesAreTexturedAndNotSaturated) {
  const PoseList trajectory = default_trajectory();
  const ProceduralWorld world(trajectory, {});
  const StereoCalibration calib = named_kitti_calibration("kitti00-02");
  StereoRenderer renderer(world, calib);
  RenderedFrame f;
  renderer.render(trajectory[200], 20.0, 200, f);
  cv::Scalar mean, stddev;
  cv::meanStdDev(f.left, mean, stddev);
  EXPECT_GT(mean[0], 60.0);
  EXPECT_LT(mean[0], 200.0);
  EXPECT_GT(stddev[0], 25.0);
  // Strong gradients everywhere in the lower two thirds (corner-rich textures), in each of 8 columns.
  for (int b = 0; b < 8; ++b) {
    const int u0 = b * calib.width / 8, u1 = (b + 1) * calib.width / 8 - 1;
    int strong = 0;
    for (int v = calib.height / 3; v < calib.height - 1; ++v) {
      for (int u = u0; u < u1; ++u) {
        if (std::abs(f.left.at<std::uint8_t>(v, u + 1) - f.left.at<std::uint8_t>(v, u)) > 20) ++strong;
      }
    }
    EXPECT_GT(strong, 300) << "column band " << b;
  }
}

TEST(DefaultTrajectory, IsACarLikeLoopOfAbout400Metres) {
  DefaultTrajectoryInfo info;
  const PoseList poses = default_trajectory(10.0, &info);
  EXPECT_GT(info.loop_length, 380.0);
  EXPECT_LT(info.loop_length, 420.0);
  EXPECT_TRUE(poses.front().matrix().isApprox(Eigen::Matrix4d::Identity(), 1e-12));
  double length = 0.0, closest_return = 1e9;
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const double step = (poses[i].translation() - poses[i - 1].translation()).norm();
    EXPECT_GT(step, 0.69);  // 7–9.5 m/s at 10 Hz
    EXPECT_LT(step, 0.96);
    // Yaw rate at most ~0.7 rad/s and smooth.
    EXPECT_LT(Eigen::AngleAxisd(poses[i - 1].linear().transpose() * poses[i].linear()).angle(), 0.07);
    length += step;
    if (length > 300.0) closest_return = std::min(closest_return, poses[i].translation().norm());
  }
  EXPECT_NEAR(length, info.total_length, 1.0);
  EXPECT_LT(closest_return, 0.5);  // drives through its start again: a loop closure
  EXPECT_GT(poses.size(), 400U);
  EXPECT_LT(poses.size(), 600U);
}

}  // namespace
}  // namespace glmbslam::sim
