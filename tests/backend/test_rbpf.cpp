// Particle filter: systematic resampling, determinism across thread counts, degenerate input, and a small
// closed-loop simulation in which the filter must track the pose far better than odometry alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "backend/rbpf/glmb_slam.hpp"
#include "backend/rbpf/resampling.hpp"
#include "core/parallel.hpp"

namespace glmbslam::backend {
namespace {

using Slam = GlmbSlam<UnicycleMotion, RangeBearingModel>;

TEST(SystematicResampling, PreservesWeightsInExpectation) {
  std::vector<double> w = {0.05, 0.3, 0.0, 0.15, 0.5};
  std::vector<double> log_w;
  for (double x : w) log_w.push_back(std::log(x));
  const int runs = 20000;
  std::vector<double> mean_count(w.size(), 0.0);
  for (int r = 0; r < runs; ++r) {
    RandomStream rng(11, r);
    const auto idx = systematic_resample(log_w, rng);
    ASSERT_EQ(idx.size(), w.size());
    std::vector<int> count(w.size(), 0);
    for (auto i : idx) ++count[i];
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double expected = w[i] * static_cast<double>(w.size());
      EXPECT_GE(count[i], std::floor(expected) - 1e-9);  // systematic: ⌊N w⌋ ≤ count ≤ ⌈N w⌉
      EXPECT_LE(count[i], std::ceil(expected) + 1e-9);
      mean_count[i] += count[i] / static_cast<double>(runs);
    }
  }
  for (std::size_t i = 0; i < w.size(); ++i) EXPECT_NEAR(mean_count[i], w[i] * w.size(), 0.02);
}

/// A small world: landmarks on a ring, the robot drives circles inside it.
struct SmallWorld {
  UnicycleMotionConfig motion_config;
  RangeBearingConfig sensor;
  std::vector<Eigen::Vector2d> landmarks;
  std::vector<Pose2> truth;
  std::vector<Eigen::Vector2d> odometry;
  std::vector<Slam::MeasurementSet> scans;

  explicit SmallWorld(int steps, std::uint64_t seed) {
    motion_config.dt = 1.0;
    motion_config.sigma_v = 0.1;
    motion_config.sigma_omega = 2.0 * M_PI / 180.0;
    sensor.sigma_range = 0.1;
    sensor.sigma_bearing = 1.0 * M_PI / 180.0;
    sensor.max_range = 7.0;
    sensor.half_fov = M_PI;
    sensor.p_detect_inside = 0.9;
    sensor.clutter_rate = 2.0;
    for (int i = 0; i < 12; ++i) {
      const double a = 2 * M_PI * i / 12.0;
      landmarks.emplace_back(11.0 * std::cos(a), 11.0 * std::sin(a));
    }
    const UnicycleMotion motion(motion_config);
    const RangeBearingModel model(sensor);
    RandomStream rng(seed, 99);
    Pose2 x(8.0, 0.0, M_PI / 2);
    truth.push_back(x);
    const Eigen::Vector2d u(1.0, 1.0 / 8.0);
    for (int k = 1; k <= steps; ++k) {
      x = motion.predict(x, u);
      truth.push_back(x);
      odometry.emplace_back(u(0) + motion_config.sigma_v * rng.normal(),
                            u(1) + motion_config.sigma_omega * rng.normal());
      Slam::MeasurementSet z;
      for (const auto& m : landmarks) {
        if (!model.in_field_of_view(x, m) || rng.uniform() > sensor.p_detect_inside) continue;
        Eigen::Vector2d zm = model.predict(x, m);
        zm(0) += sensor.sigma_range * rng.normal();
        zm(1) = wrap_angle(zm(1) + sensor.sigma_bearing * rng.normal());
        z.push_back(zm);
      }
      const int clutter = rng.poisson(sensor.clutter_rate);
      for (int c = 0; c < clutter; ++c)
        z.emplace_back(rng.uniform(sensor.min_range, sensor.max_range), rng.uniform(-M_PI, M_PI));
      scans.push_back(z);
    }
  }
};

RbpfConfig small_config(const std::string& proposal) {
  RbpfConfig c;
  c.particles = 10;
  c.seed = 5;
  c.proposal = proposal;
  return c;
}

Slam::PoseList run(const SmallWorld& world, const RbpfConfig& config, int steps) {
  Slam slam(UnicycleMotion(world.motion_config), RangeBearingModel(world.sensor), config, world.truth[0]);
  Slam::PoseList poses{world.truth[0]};
  for (int k = 0; k < steps; ++k) {
    slam.step(world.odometry[k], world.scans[k]);
    poses.push_back(slam.pose());
  }
  return poses;
}

TEST(GlmbSlam, SameSeedSameOutputWhateverTheThreadCount) {
  const SmallWorld world(30, 1);
  const int threads = thread_count();
  for (const std::string proposal : {"prior", "optimal"}) {
    set_thread_count(1);
    const auto a = run(world, small_config(proposal), 30);
    set_thread_count(2);
    const auto b = run(world, small_config(proposal), 30);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << proposal << " step " << k;
  }
  set_thread_count(threads);
}

// single_particle "mean" with one particle: every pose is the proposal mean (the recorded point estimate);
// "sample" draws around it; with more particles the setting changes nothing.
TEST(GlmbSlam, SingleParticleMeanTakesTheProposalMean) {
  const SmallWorld world(20, 2);
  auto trajectories = [&](int particles, const std::string& mode) {
    RbpfConfig c = small_config("optimal");
    c.particles = particles;
    c.single_particle = mode;
    Slam slam(UnicycleMotion(world.motion_config), RangeBearingModel(world.sensor), c, world.truth[0]);
    for (int k = 0; k < 20; ++k) slam.step(world.odometry[k], world.scans[k]);
    return std::make_pair(slam.trajectory(), slam.estimated_trajectory());
  };
  const auto [mean_poses, mean_estimates] = trajectories(1, "mean");
  ASSERT_EQ(mean_poses.size(), 21u);
  for (std::size_t k = 0; k < mean_poses.size(); ++k) EXPECT_EQ(mean_poses[k], mean_estimates[k]) << k;
  const auto [sample_poses, sample_estimates] = trajectories(1, "sample");
  int differ = 0;
  for (std::size_t k = 1; k < sample_poses.size(); ++k) differ += !(sample_poses[k] == sample_estimates[k]);
  EXPECT_EQ(differ, 20);
  const auto four_mean = trajectories(4, "mean");
  const auto four_sample = trajectories(4, "sample");
  EXPECT_EQ(four_mean.first, four_sample.first);
}

TEST(GlmbSlam, RejectsNonFiniteInputWithoutChangingState) {
  const SmallWorld world(2, 2);
  Slam slam(UnicycleMotion(world.motion_config), RangeBearingModel(world.sensor), small_config("optimal"),
            world.truth[0]);
  Slam::MeasurementSet z = world.scans[0];
  z.emplace_back(std::nan(""), 0.0);
  EXPECT_THROW(slam.step(world.odometry[0], z), InputError);
  EXPECT_THROW(slam.step(Eigen::Vector2d(std::nan(""), 0.0), world.scans[0]), InputError);
  EXPECT_EQ(slam.steps(), 0);
  slam.step(world.odometry[0], Slam::MeasurementSet{});  // empty scan is fine
  EXPECT_EQ(slam.steps(), 1);
}

// A frame whose sensor saw nothing (blind_step): every particle keeps the map it had and its weight, and its
// pose moves by the motion model's prediction, undrawn.
// An empty scan is different: the landmarks in view were missed, and their existence falls.
TEST(GlmbSlam, ABlindStepMovesThePosesAndLeavesTheMaps) {
  const SmallWorld world(12, 4);
  for (const int particles : {1, 10}) {
    RbpfConfig c = small_config("optimal");
    c.particles = particles;
    c.single_particle = "mean";
    c.resampling = "ess";
    Slam slam(UnicycleMotion(world.motion_config), RangeBearingModel(world.sensor), c, world.truth[0]);
    for (int k = 0; k < 10; ++k) slam.step(world.odometry[k], world.scans[k]);
    std::vector<const Slam::Map*> maps;
    std::vector<double> log_w;
    for (const auto& p : slam.particles()) {
      maps.push_back(p.map.get());
      log_w.push_back(p.log_weight);
    }
    const auto landmarks = slam.landmarks();
    ASSERT_FALSE(landmarks.empty());
    const Pose2 before = slam.pose();
    const Eigen::Vector2d u = world.odometry[10];
    slam.blind_step(u);
    EXPECT_EQ(slam.steps(), 11);
    EXPECT_EQ(slam.trajectory().size(), 12u);
    EXPECT_NEAR(slam.last_report().ess, effective_sample_size(log_w), 1e-9 * particles) << particles;
    const UnicycleMotion motion(world.motion_config);
    for (const auto& p : slam.particles()) {
      EXPECT_NE(std::find(maps.begin(), maps.end(), p.map.get()), maps.end()) << particles;
      EXPECT_EQ(p.trajectory->pose, motion.predict(p.trajectory->parent->pose, u)) << particles;
    }
    const auto after = slam.landmarks();
    ASSERT_EQ(after.size(), landmarks.size());
    for (std::size_t j = 0; j < after.size(); ++j) {
      EXPECT_EQ(after[j].label, landmarks[j].label);
      EXPECT_EQ(after[j].existence, landmarks[j].existence);
      EXPECT_EQ(after[j].mean, landmarks[j].mean);
    }
    if (particles == 1) {
      EXPECT_EQ(slam.pose(), UnicycleMotion(world.motion_config).predict(before, u));
      // the same step with an empty scan instead: the landmarks in view were missed
      Slam missed(UnicycleMotion(world.motion_config), RangeBearingModel(world.sensor), c, world.truth[0]);
      for (int k = 0; k < 10; ++k) missed.step(world.odometry[k], world.scans[k]);
      missed.step(u, Slam::MeasurementSet{});
      const RangeBearingModel model(world.sensor);
      const auto missed_landmarks = missed.landmarks();
      int in_view = 0;
      for (const auto& l : after) {
        if (!model.in_field_of_view(missed.pose(), l.mean)) continue;
        ++in_view;
        for (const auto& m : missed_landmarks) {
          if (m.label == l.label) {
            EXPECT_LT(m.existence, l.existence);
          }
        }
      }
      EXPECT_GT(in_view, 0);
    }
  }
}

double position_rmse(const SmallWorld& world, const Slam::PoseList& est) {
  double s = 0.0;
  for (std::size_t k = 0; k < est.size(); ++k) s += (est[k] - world.truth[k]).head<2>().squaredNorm();
  return std::sqrt(s / static_cast<double>(est.size()));
}

TEST(GlmbSlam, TracksThePoseInASmallSimulation) {
  const int steps = 100;
  const SmallWorld world(steps, 3);
  // dead reckoning with the noisy odometry
  const UnicycleMotion motion(world.motion_config);
  Slam::PoseList odo{world.truth[0]};
  for (int k = 0; k < steps; ++k) odo.push_back(motion.predict(odo.back(), world.odometry[k]));
  const double odo_rmse = position_rmse(world, odo);
  for (const std::string proposal : {"prior", "optimal"}) {
    const auto est = run(world, small_config(proposal), steps);
    const double rmse = position_rmse(world, est);
    std::printf("%s: position RMSE %.3f m (odometry %.3f m), final error %.3f m\n", proposal.c_str(), rmse,
                odo_rmse, (est.back() - world.truth.back()).head<2>().norm());
    EXPECT_LT(rmse, 0.5 * odo_rmse) << proposal;
    EXPECT_LT(rmse, 1.0) << proposal;
  }
}

}  // namespace
}  // namespace glmbslam::backend
