// Frontend and VO speed on KITTI raw drive 0001 (1242×375, 2000 features): per-stage median and p95 over all
// frames of the thread CPU time on one core (OpenCV threads = 1, left/right extraction in sequence), then the
// wall time of the app's path (extractions in parallel), then Google Benchmark micro-benchmarks of the
// stages. Run: bench_frontend [--benchmark_filter=...]   (GLMBSLAM_DATA overrides the data folder;
//      GLMBSLAM_BENCH_CPU_ONLY=1 prints only the one-core CPU report, GLMBSLAM_BENCH_FRAMES=N uses N frames)
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/random.hpp"
#include "core/stopwatch.hpp"
#include "frontend/stereo_frontend.hpp"
#include "frontend/stereo_pose_refiner.hpp"
#include "frontend/visual_odometry.hpp"

namespace {

using namespace glmbslam;

std::filesystem::path drive_dir() {
  const char* env = std::getenv("GLMBSLAM_DATA");
  const std::filesystem::path data = env != nullptr && *env != '\0' ? env : GLMBSLAM_DEFAULT_DATA_DIR;
  return data / "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync";
}

StereoCalibration calibration() {
  StereoCalibration c;
  c.fx = c.fy = 721.5377;
  c.cx = 609.5593;
  c.cy = 172.854;
  c.baseline = 387.5744 / 721.5377;
  c.width = 1242;
  c.height = 375;
  return c;
}

struct Pair {
  cv::Mat left, right;
};

const std::vector<Pair>& frames() {
  static const std::vector<Pair> f = [] {
    std::vector<Pair> v;
    const char* limit = std::getenv("GLMBSLAM_BENCH_FRAMES");
    const int max_frames = limit != nullptr ? std::atoi(limit) : 1 << 30;
    for (int i = 0; i < max_frames; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "%010d.png", i);
      Pair p{cv::imread((drive_dir() / "image_00/data" / name).string(), cv::IMREAD_GRAYSCALE),
             cv::imread((drive_dir() / "image_01/data" / name).string(), cv::IMREAD_GRAYSCALE)};
      if (p.left.empty() || p.right.empty()) break;
      v.push_back(p);
    }
    return v;
  }();
  return f;
}

double thread_cpu_ms() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

void print_stage(const char* name, const std::vector<double>& v) {
  const SampleSummary s = summarize(v);
  std::printf("  %-34s median %7.2f ms   p95 %7.2f ms\n", name, s.median, s.p95);
}

// One core: every stage on this thread (extractions in sequence), thread CPU time per stage.
void cpu_stage_report() {
  const frontend::FrontendConfig config;
  const frontend::OrbExtractor extractor(config.orb);
  const frontend::StereoFrontend fe(calibration(), config);
  const frontend::StereoMatcher matcher(fe.camera(), config.stereo, extractor.scales());
  frontend::StereoVisualOdometry vo(fe.camera(), config.vo, extractor.scales());
  std::vector<double> extract_cpu, match_cpu, fe_cpu, vo_cpu, total_cpu;
  std::vector<double> measurements, inliers;
  for (const Pair& p : frames()) {
    frontend::StereoFrameFeatures f;
    const double c0 = thread_cpu_ms();
    f.left = extractor.extract(p.left);
    f.right = extractor.extract(p.right);
    const double c1 = thread_cpu_ms();
    f.measurements = matcher.match(f.left, f.right, &f.left_to_measurement, &f.stats);
    const double c2 = thread_cpu_ms();
    const frontend::VoEstimate e = vo.track(f);
    const double c3 = thread_cpu_ms();
    extract_cpu.push_back(c1 - c0);
    match_cpu.push_back(c2 - c1);
    fe_cpu.push_back(c2 - c0);
    vo_cpu.push_back(c3 - c2);
    total_cpu.push_back(c3 - c0);
    measurements.push_back(static_cast<double>(f.measurements.size()));
    inliers.push_back(e.inliers);
  }
  std::printf("one core, CPU time per frame, %zu frames:\n", frames().size());
  print_stage("ORB extraction, both images", extract_cpu);
  print_stage("stereo matching + triangulation", match_cpu);
  print_stage("frontend (extract + match)", fe_cpu);
  print_stage("VO", vo_cpu);
  print_stage("frontend + VO", total_cpu);
  std::printf("  stereo measurements per frame median %.0f, VO inliers median %.0f\n",
              summarize(measurements).median, summarize(inliers).median);
}

// The app's path: StereoFrontend::process (left/right extraction on two threads), wall time.
void parallel_wall_report() {
  const frontend::FrontendConfig config;
  const frontend::StereoFrontend fe(calibration(), config);
  frontend::StereoVisualOdometry vo(fe.camera(), config.vo, fe.extractor().scales());
  std::vector<double> fe_wall, ex_wall, match_wall, vo_wall;
  for (const Pair& p : frames()) {
    Stopwatch sw;
    const frontend::StereoFrameFeatures f = fe.process(p.left, p.right);
    fe_wall.push_back(sw.elapsed_ms());
    ex_wall.push_back(f.extract_ms);
    match_wall.push_back(f.match_ms);
    vo_wall.push_back(vo.track(f).ms);
  }
  std::printf(
      "left/right extraction in parallel (2 threads), wall time (depends on machine load), %zu frames:\n",
      frames().size());
  print_stage("frontend (extract + match)", fe_wall);
  print_stage("  ORB extraction, both images", ex_wall);
  print_stage("  stereo matching", match_wall);
  print_stage("VO", vo_wall);
}

void BM_OrbExtractOneImage(benchmark::State& state) {
  const frontend::OrbExtractor ex(frontend::OrbConfig{});
  const cv::Mat& img = frames()[50].left;
  for (auto _ : state) benchmark::DoNotOptimize(ex.extract(img));
}
BENCHMARK(BM_OrbExtractOneImage)->Unit(benchmark::kMillisecond);

void BM_StereoFrontend(benchmark::State& state) {
  frontend::FrontendConfig config;
  config.orb.parallel = state.range(0) != 0;
  const frontend::StereoFrontend fe(calibration(), config);
  for (auto _ : state) benchmark::DoNotOptimize(fe.process(frames()[50].left, frames()[50].right));
}
BENCHMARK(BM_StereoFrontend)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg: frontend.stereo.gain_compensation off (0) / on (1).
void BM_StereoMatching(benchmark::State& state) {
  frontend::FrontendConfig config;
  config.stereo.gain_compensation = state.range(0) != 0;
  const frontend::StereoFrontend fe(calibration(), config);
  const frontend::StereoFrameFeatures f = fe.process(frames()[50].left, frames()[50].right);
  const frontend::StereoMatcher matcher(fe.camera(), config.stereo, fe.extractor().scales());
  std::vector<int> l2m;
  for (auto _ : state) benchmark::DoNotOptimize(matcher.match(f.left, f.right, &l2m));
}
BENCHMARK(BM_StereoMatching)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_VoTrack(benchmark::State& state) {
  const frontend::FrontendConfig config;
  const frontend::StereoFrontend fe(calibration(), config);
  const frontend::StereoFrameFeatures a = fe.process(frames()[50].left, frames()[50].right);
  const frontend::StereoFrameFeatures b = fe.process(frames()[51].left, frames()[51].right);
  for (auto _ : state) {
    state.PauseTiming();
    frontend::StereoVisualOdometry vo(fe.camera(), config.vo, fe.extractor().scales());
    vo.track(a);
    state.ResumeTiming();
    benchmark::DoNotOptimize(vo.track(b));
  }
}
BENCHMARK(BM_VoTrack)->Unit(benchmark::kMillisecond);

// Motion-only refinement alone on a synthetic problem of KITTI size (600 tracked points, a quarter seen in
// the current left image only, 15 % outliers, 1 px noise), VO default options; Arg 0 = Ceres, 1 =
// Gauss–Newton.
void BM_StereoPoseRefiner(benchmark::State& state) {
  const StereoCamera camera(calibration());
  RandomStream rng(7);
  Vector6d motion = Vector6d::Zero();
  motion << 0.05, 0.0, 1.0, 0.0, 0.02, 0.0;
  const Pose3 truth = se3_exp(motion);
  std::vector<frontend::TrackedPoint> points;
  while (points.size() < 600) {
    const Eigen::Vector3d X(rng.uniform(-12, 12), rng.uniform(-3, 2), rng.uniform(4, 50));
    const Eigen::Vector3d pc = truth.inverse() * X;
    if (pc.z() < 2.0) continue;
    frontend::TrackedPoint t;
    t.z_ref = camera.project(X) + Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    t.z_cur = camera.project(pc) + Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    if (rng.uniform() < 0.15) t.z_cur += Eigen::Vector3d(rng.uniform(8, 30), rng.uniform(-30, 30), 0.0);
    t.point_ref = camera.triangulate(t.z_ref);
    t.cur_stereo = points.size() % 4 != 0;
    points.push_back(t);
  }
  frontend::PoseRefinementOptions options = frontend::pose_refinement_options(frontend::VoConfig{});
  options.refiner =
      state.range(0) == 0 ? frontend::PoseRefinerKind::kCeres : frontend::PoseRefinerKind::kGaussNewton;
  const Pose3 start = se3_plus(truth, (Vector6d() << 0.02, -0.01, 0.03, 0.002, -0.003, 0.001).finished());
  for (auto _ : state) benchmark::DoNotOptimize(frontend::refine_stereo_pose(camera, points, start, options));
}
BENCHMARK(BM_StereoPoseRefiner)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  spdlog::set_level(spdlog::level::warn);
  cv::setNumThreads(1);
  if (frames().empty()) {
    std::printf("KITTI raw drive 0001 not found under %s; set GLMBSLAM_DATA\n", drive_dir().string().c_str());
    return 0;
  }
  cpu_stage_report();
  if (std::getenv("GLMBSLAM_BENCH_CPU_ONLY") == nullptr) parallel_wall_report();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
