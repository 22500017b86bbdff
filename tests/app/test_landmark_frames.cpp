// move_with_birth_frames (app/pipeline/landmark_frames.hpp): each landmark keeps its position relative to
// the frame that first mapped it, checked on known geometry.
#include <gtest/gtest.h>

#include "app/pipeline/filter_stage.hpp"
#include "app/pipeline/landmark_frames.hpp"

namespace glmbslam::app {
namespace {

io::MapPoint landmark_born_at(std::int32_t birth, std::int32_t index, const Eigen::Vector3d& p) {
  return io::MapPoint{p, pack_label(backend::Label{birth, index}), 1.0};
}

TEST(LandmarkFrames, EachLandmarkFollowsTheCorrectionOfItsBirthFrame) {
  // from: the camera at the origin, then 1 m forward; to: frame 0 unchanged, frame 1 turned 90° about the
  // vertical axis and moved 2 m to the side
  PoseList from{Pose3::Identity(), Pose3(Eigen::Translation3d(0.0, 0.0, 1.0))};
  Pose3 turned = Pose3::Identity();
  turned.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  turned.translation() = Eigen::Vector3d(2.0, 0.0, 1.0);
  const PoseList to{Pose3::Identity(), turned};
  std::vector<io::MapPoint> map{landmark_born_at(0, 3, {1.0, 2.0, 3.0}),
                                landmark_born_at(1, 7, {0.0, 0.0, 6.0}),   // 5 m ahead of frame 1
                                landmark_born_at(9, 1, {4.0, 5.0, 6.0})};  // born after the trajectory
  move_with_birth_frames(map, from, to);
  EXPECT_TRUE(map[0].position.isApprox(Eigen::Vector3d(1.0, 2.0, 3.0), 1e-12)) << map[0].position.transpose();
  // 5 m along frame 1's optical axis, which now points along +x: (2 + 5, 0, 1)
  EXPECT_TRUE(map[1].position.isApprox(Eigen::Vector3d(7.0, 0.0, 1.0), 1e-12)) << map[1].position.transpose();
  EXPECT_TRUE(map[2].position.isApprox(Eigen::Vector3d(4.0, 5.0, 6.0), 1e-12)) << map[2].position.transpose();
  EXPECT_EQ(map[1].label, pack_label(backend::Label{1, 7}));  // labels and order kept
  EXPECT_EQ(label_birth_step(map[1].label), 1u);
}

TEST(LandmarkFrames, TheSameTrajectoryMovesNothing) {
  const PoseList poses{Pose3::Identity(), Pose3(Eigen::Translation3d(0.5, -0.2, 1.0))};
  std::vector<io::MapPoint> map{landmark_born_at(1, 0, {0.3, 0.1, 8.0})};
  move_with_birth_frames(map, poses, poses);
  EXPECT_TRUE(map[0].position.isApprox(Eigen::Vector3d(0.3, 0.1, 8.0), 1e-12));
}

}  // namespace
}  // namespace glmbslam::app
