// Speed of the synthetic stereo renderer (stereo pairs per second on one core at 1241×376) and ORB feature
// counts of its images. The CPU column is the figure to read on a shared machine.
//   build-*/bench/bench_render [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <vector>

#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "io/trajectory_io.hpp"
#include "sim/default_trajectory.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "sim/png_writer.hpp"
#include "sim/stereo_procedural_world.hpp"
#include "sim/stereo_renderer.hpp"

namespace {
using namespace glmbslam;

const PoseList& kitti00() {
  static const PoseList poses = [] {
    const auto path = std::filesystem::path(GLMBSLAM_DEFAULT_DATA_DIR) / "kitti_odometry/poses/00.txt";
    return std::filesystem::exists(path) ? io::read_kitti_poses(path.string()) : sim::default_trajectory();
  }();
  return poses;
}

void run_render(benchmark::State& state, const PoseList& trajectory, int movers) {
  sim::ProceduralWorldOptions wopt;
  wopt.movers = movers;
  const sim::ProceduralWorld world(trajectory, wopt);
  sim::StereoRenderer renderer(world, sim::named_kitti_calibration("kitti00-02"));
  sim::RenderedFrame frame;
  std::size_t i = 0;
  for (auto _ : state) {
    renderer.render(trajectory[i], 0.1 * static_cast<double>(i), i, frame, false);
    benchmark::DoNotOptimize(frame.left.data);
    i = (i + 7) % trajectory.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));  // stereo pairs
}

void BM_RenderStereoPairDefaultTrajectory(benchmark::State& state) {
  run_render(state, sim::default_trajectory(), 0);
}
BENCHMARK(BM_RenderStereoPairDefaultTrajectory)->Unit(benchmark::kMillisecond);

void BM_RenderStereoPairKitti00(benchmark::State& state) {
  run_render(state, kitti00(), 0);
}
BENCHMARK(BM_RenderStereoPairKitti00)->Unit(benchmark::kMillisecond);

void BM_RenderStereoPairKitti00Movers(benchmark::State& state) {
  run_render(state, kitti00(), 8);
}
BENCHMARK(BM_RenderStereoPairKitti00Movers)->Unit(benchmark::kMillisecond);

void BM_EncodePng(benchmark::State& state) {
  const PoseList trajectory = sim::default_trajectory();
  const sim::ProceduralWorld world(trajectory, {});
  sim::StereoRenderer renderer(world, sim::named_kitti_calibration("kitti00-02"));
  sim::RenderedFrame frame;
  renderer.render(trajectory[100], 10.0, 100, frame, false);
  std::vector<uchar> buffer;
  const std::vector<int> params = sim::png_parameters(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    cv::imencode(".png", frame.left, buffer, params);
    benchmark::DoNotOptimize(buffer.data());
  }
  state.counters["bytes"] = static_cast<double>(buffer.size());
}
BENCHMARK(BM_EncodePng)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

/// The built-in encoder the sequence writer uses at its default level 1 (Sub filter + Huffman-only deflate).
void BM_EncodePngFast(benchmark::State& state) {
  const PoseList trajectory = sim::default_trajectory();
  const sim::ProceduralWorld world(trajectory, {});
  sim::StereoRenderer renderer(world, sim::named_kitti_calibration("kitti00-02"));
  sim::RenderedFrame frame;
  renderer.render(trajectory[100], 10.0, 100, frame, false);
  sim::PngScratch scratch;
  for (auto _ : state) {
    sim::encode_png_gray8(frame.left, scratch);
    benchmark::DoNotOptimize(scratch.encoded.data());
  }
  state.counters["bytes"] = static_cast<double>(scratch.encoded.size());
}
BENCHMARK(BM_EncodePngFast)->Unit(benchmark::kMillisecond);

/// ORB keypoints per image (FAST threshold 20, up to 5000) over frames of sequence 00: min and mean.
void BM_OrbFeatureCount(benchmark::State& state) {
  const PoseList& trajectory = kitti00();
  const sim::ProceduralWorld world(trajectory, {});
  sim::StereoRenderer renderer(world, sim::named_kitti_calibration("kitti00-02"));
  sim::RenderedFrame frame;
  auto orb = cv::ORB::create(5000);
  std::vector<cv::KeyPoint> keypoints;
  double min_count = 1e9, sum = 0.0;
  int n = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < trajectory.size(); i += 150) {
      renderer.render(trajectory[i], 0.1 * static_cast<double>(i), i, frame, false);
      orb->detect(frame.left, keypoints);
      min_count = std::min(min_count, static_cast<double>(keypoints.size()));
      sum += static_cast<double>(keypoints.size());
      ++n;
    }
  }
  state.counters["orb_min"] = min_count;
  state.counters["orb_mean"] = sum / n;
}
BENCHMARK(BM_OrbFeatureCount)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
