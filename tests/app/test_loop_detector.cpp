// app/pipeline/loop_detector.hpp: the relative pose of two views of the same points recovered from their
// descriptors and stereo measurements; unrelated views give nothing; a revisit along a trajectory is found.
#include <cmath>

#include <gtest/gtest.h>

#include "app/pipeline/loop_detector.hpp"
#include "core/random.hpp"
#include "sim/kitti_sequence_writer.hpp"

namespace glmbslam::app {
namespace {

StereoCalibration kitti_like() {
  return sim::named_kitti_calibration("kitti00-02");
}

std::array<std::uint8_t, 32> random_descriptor(RandomStream& rng) {
  std::array<std::uint8_t, 32> d{};
  for (auto& byte : d) byte = static_cast<std::uint8_t>(rng.index(256));
  return d;
}

/// A world of points in front of the origin (3–20 m deep), each with its own descriptor.
struct Scene {
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> points;
  std::vector<std::array<std::uint8_t, 32>> descriptors;
};

Scene make_scene(std::uint64_t seed, int n) {
  RandomStream rng(seed);
  Scene s;
  for (int i = 0; i < n; ++i) {
    const double z = rng.uniform(3.0, 20.0);
    s.points.emplace_back(rng.uniform(-0.6, 0.6) * z, rng.uniform(-0.15, 0.15) * z, z);
    s.descriptors.push_back(random_descriptor(rng));
  }
  return s;
}

/// The stereo measurements of `scene` from the camera at `pose` (world ← camera), with pixel noise and up to
/// 3 flipped descriptor bits, plus `clutter` points with unrelated descriptors.
frontend::StereoMeasurementList observe(const Scene& scene, const Pose3& pose, const StereoCamera& camera,
                                        std::uint64_t seed, int clutter) {
  RandomStream rng(seed, 7);
  frontend::StereoMeasurementList out;
  auto add = [&](const Eigen::Vector3d& p, std::array<std::uint8_t, 32> d) {
    if (p.z() < 1.0) return;
    frontend::StereoMeasurement m;
    m.z = camera.project(p) + Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal()) * 0.3;
    if (m.z.x() - m.z.z() <= 0.5) return;
    m.point = camera.triangulate(m.z);
    for (int f = 0; f < 3; ++f) {
      const std::size_t bit = rng.index(256);
      d[bit / 8] = static_cast<std::uint8_t>(d[bit / 8] ^ (1u << (bit % 8)));
    }
    m.descriptor = d;
    m.response = static_cast<float>(rng.uniform(10.0, 100.0));
    out.push_back(m);
  };
  for (std::size_t i = 0; i < scene.points.size(); ++i)
    add(pose.inverse() * scene.points[i], scene.descriptors[i]);
  for (int c = 0; c < clutter; ++c)
    add(Eigen::Vector3d(rng.uniform(-3.0, 3.0), rng.uniform(-1.0, 1.0), rng.uniform(4.0, 15.0)),
        random_descriptor(rng));
  return out;
}

Pose3 moved(double forward, double yaw_deg) {
  Pose3 T = Pose3::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.2, 0.0, forward);
  return T;
}

/// The keyframe of frame k: its measurements within the default depth limit.
LoopKeyframe keyframe_of(std::size_t k, const frontend::StereoMeasurementList& measurements) {
  LoopKeyframe kf;
  kf.k = k;
  for (const auto& m : measurements) {
    if (m.point.z() > LoopDetectorOptions{}.max_depth_m) continue;
    kf.points.push_back(m.point);
    kf.descriptors.push_back(m.descriptor);
  }
  return kf;
}

TEST(LoopDetector, RecoversTheRelativePoseOfTwoViewsOfOnePlace) {
  const StereoCamera camera(kitti_like());
  const Scene scene = make_scene(1, 250);
  const Pose3 T_ab = moved(1.5, 4.0);  // b's camera in a's frame
  const LoopKeyframe a = keyframe_of(0, observe(scene, Pose3::Identity(), camera, 2, 40));
  const LoopKeyframe b = keyframe_of(500, observe(scene, T_ab, camera, 3, 40));
  const auto m = match_keyframes(a, b, camera, LoopDetectorOptions{}, 11);
  ASSERT_TRUE(m.has_value());
  EXPECT_GT(m->inliers, 150u);
  EXPECT_LT((m->T_ab.translation() - T_ab.translation()).norm(), 0.02);
  EXPECT_LT(rotation_angle(m->T_ab.linear().transpose() * T_ab.linear()), 0.2 * M_PI / 180.0);
  // reproducible: the same seed gives the same pose
  const auto again = match_keyframes(a, b, camera, LoopDetectorOptions{}, 11);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->T_ab.matrix(), m->T_ab.matrix());
}

TEST(LoopDetector, UnrelatedPlacesDoNotMatch) {
  const StereoCamera camera(kitti_like());
  const LoopKeyframe a = keyframe_of(0, observe(make_scene(1, 250), Pose3::Identity(), camera, 2, 40));
  const LoopKeyframe b = keyframe_of(500, observe(make_scene(2, 250), Pose3::Identity(), camera, 3, 40));
  EXPECT_FALSE(match_keyframes(a, b, camera, LoopDetectorOptions{}, 11).has_value());
}

TEST(LoopDetector, FindsTheRevisitOfADriftedTrajectory) {
  const StereoCamera camera(kitti_like());
  const Scene place = make_scene(1, 250);
  // 400 frames: the place is seen at frames 0 and 300 (true relative pose T_ab); every other keyframe sees
  // a scene of its own. The trajectory handed to detect() has drifted 3 m by the revisit.
  const Pose3 T_ab = moved(0.8, -3.0);
  LoopDetectorOptions options;
  LoopDetector detector(options, kitti_like());
  PoseList trajectory;
  for (std::size_t k = 0; k < 400; ++k) {
    Pose3 x = Pose3::Identity();
    x.translation() = Eigen::Vector3d(0.0, 0.0, static_cast<double>(k < 200 ? k : 400 - k));  // out and back
    if (k == 300) x = T_ab;                                           // the revisit, in the true frame …
    if (k >= 200) x.translation() += Eigen::Vector3d(3.0, 0.0, 0.0);  // … then drifted by 3 m
    trajectory.push_back(x);
    if (k % options.keyframe_every != 0) continue;
    if (k == 0 || k == 300) {
      detector.add_frame(k, observe(place, k == 0 ? Pose3::Identity() : T_ab, camera, k + 5, 40));
    } else {
      detector.add_frame(k, observe(make_scene(1000 + k, 250), Pose3::Identity(), camera, k + 5, 40));
    }
  }
  const std::vector<backend::LoopConstraint> loops = detector.detect(trajectory);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].i, 0u);
  EXPECT_EQ(loops[0].j, 300u);
  EXPECT_LT((loops[0].relative.translation() - T_ab.translation()).norm(), 0.02);
}

}  // namespace
}  // namespace glmbslam::app
