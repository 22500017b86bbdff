// Timing of the trajectory evaluation on KITTI sequence 00 (4541 poses, ORB-SLAM2 stereo result) and of the
// linear assignment behind OSPA/GOSPA. Skips (with a message) when ../shared/data is absent.
#include <cstdlib>
#include <filesystem>

#include <benchmark/benchmark.h>

#include "core/linear_assignment.hpp"
#include "core/random.hpp"
#include "eval/kitti_metric.hpp"
#include "eval/ospa.hpp"
#include "eval/report.hpp"
#include "io/trajectory_io.hpp"

namespace {

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("GLMBSLAM_DATA"); env != nullptr && *env != '\0') return env;
  return GLMBSLAM_DEFAULT_DATA_DIR;
}

struct Sequence00 {
  glmbslam::PoseList gt, est;
  bool ok = false;
  Sequence00() {
    const auto d = data_dir() / "kitti_odometry";
    if (!std::filesystem::exists(d / "poses/00.txt")) return;
    gt = glmbslam::io::read_kitti_poses((d / "poses/00.txt").string());
    est = glmbslam::io::read_kitti_poses((d / "results/00_orbslam2_stereo.txt").string());
    ok = true;
  }
};

const Sequence00& sequence00() {
  static const Sequence00 s;
  return s;
}

void BM_ReadPosePair(benchmark::State& state) {
  const auto d = data_dir() / "kitti_odometry";
  if (!std::filesystem::exists(d / "poses/00.txt")) {
    state.SkipWithError("shared data not found");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(glmbslam::io::read_kitti_poses((d / "poses/00.txt").string()));
    benchmark::DoNotOptimize(glmbslam::io::read_kitti_poses((d / "results/00_orbslam2_stereo.txt").string()));
  }
}
BENCHMARK(BM_ReadPosePair)->Unit(benchmark::kMillisecond);

void BM_KittiMetric(benchmark::State& state) {
  const auto& s = sequence00();
  if (!s.ok) {
    state.SkipWithError("shared data not found");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(glmbslam::eval::evaluate_kitti(s.gt, s.est));
}
BENCHMARK(BM_KittiMetric)->Unit(benchmark::kMillisecond);

void BM_FullEvaluation(benchmark::State& state) {
  const auto& s = sequence00();
  if (!s.ok) {
    state.SkipWithError("shared data not found");
    return;
  }
  for (auto _ : state) {
    const auto e = glmbslam::eval::evaluate_trajectory(s.gt, s.est);
    benchmark::DoNotOptimize(glmbslam::eval::to_json(e).dump());
  }
}
BENCHMARK(BM_FullEvaluation)->Unit(benchmark::kMillisecond);

void BM_LinearAssignment(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  glmbslam::RandomStream rng(1);
  Eigen::MatrixXd c(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) c(i, j) = rng.uniform(0.0, 100.0);
  for (auto _ : state) benchmark::DoNotOptimize(glmbslam::solve_linear_assignment(c));
  state.SetComplexityN(n);
}
BENCHMARK(BM_LinearAssignment)->RangeMultiplier(4)->Range(8, 512)->Complexity(benchmark::oNCubed);

void BM_Gospa3d(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  glmbslam::RandomStream rng(2);
  Eigen::MatrixXd x(3, n), y(3, n);
  for (int j = 0; j < n; ++j)
    for (int d = 0; d < 3; ++d) {
      x(d, j) = rng.uniform(0.0, 100.0);
      y(d, j) = x(d, j) + rng.normal(0.0, 1.0);
    }
  for (auto _ : state) benchmark::DoNotOptimize(glmbslam::eval::gospa(x, y, 5.0, 2.0));
}
BENCHMARK(BM_Gospa3d)->Arg(100)->Arg(1000);

}  // namespace

BENCHMARK_MAIN();
