#include <gtest/gtest.h>

#include "core/error.hpp"
#include "eval/association.hpp"

namespace glmbslam::eval {
namespace {

io::Trajectory make(const std::vector<double>& stamps) {
  io::Trajectory t;
  for (double s : stamps) {
    Pose3 T = Pose3::Identity();
    T.translation().x() = s;  // remember the stamp in the pose
    t.poses.push_back(T);
    t.timestamps.push_back(s);
  }
  return t;
}

TEST(Association, ByIndexRequiresSameCount) {
  const PoseList a(3, Pose3::Identity()), b(4, Pose3::Identity());
  EXPECT_EQ(associate_by_index(a, a, "est.txt").gt.size(), 3u);
  try {
    associate_by_index(a, b, "est.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "est.txt");
    EXPECT_NE(std::string(e.what()).find("4 poses"), std::string::npos);
  }
}

TEST(Association, ByTimestampNearestWithinTolerance) {
  const io::Trajectory gt = make({0.0, 0.1, 0.2, 0.3, 0.4, 0.5});
  const io::Trajectory est = make({0.005, 0.13, 0.21, 0.36, 0.9});
  // 0.005→0.0, 0.13→0.1 (0.03 > 0.02: unmatched), 0.21→0.2, 0.36→0.4 (0.04: unmatched), 0.9 unmatched.
  const AssociatedTrajectories a = associate_by_timestamp(gt, est, 0.02, "est.txt");
  ASSERT_EQ(a.gt.size(), 2u);
  EXPECT_DOUBLE_EQ(a.timestamps[0], 0.0);
  EXPECT_DOUBLE_EQ(a.timestamps[1], 0.2);
  EXPECT_DOUBLE_EQ(a.est[1].translation().x(), 0.21);
  EXPECT_EQ(a.unmatched_est, 3);
  const AssociatedTrajectories wide = associate_by_timestamp(gt, est, 0.05, "est.txt");
  EXPECT_EQ(wide.gt.size(), 4u);
  EXPECT_DOUBLE_EQ(wide.timestamps[3], 0.4);
}

TEST(Association, OneToOne) {
  // Two estimates near the same ground-truth stamp: only the first gets it; the second takes the next one if
  // close.
  const io::Trajectory gt = make({1.0, 2.0, 3.0});
  const io::Trajectory est = make({1.0, 1.01, 2.0});
  const AssociatedTrajectories a = associate_by_timestamp(gt, est, 0.02, "est.txt");
  ASSERT_EQ(a.gt.size(), 2u);
  EXPECT_DOUBLE_EQ(a.timestamps[0], 1.0);
  EXPECT_DOUBLE_EQ(a.timestamps[1], 2.0);
  EXPECT_EQ(a.unmatched_est, 1);
}

TEST(Association, TooFewPairsIsAnError) {
  EXPECT_THROW(associate_by_timestamp(make({0.0, 1.0}), make({5.0, 6.0}), 0.02, "est.txt"), InputError);
  try {  // the message gives both time ranges (a clock offset or a unit shows there) and the window
    associate_by_timestamp(make({0.0, 1.0}), make({5.0, 6.0}), 0.02, "est.txt");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("within 0.02 s (estimate 5.000…6.000 s, ground truth 0.000…1.000 s"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace glmbslam::eval
