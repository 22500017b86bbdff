// A run stopped by a signal keeps its work: `glmbslam run` on a short rendered sequence is sent SIGTERM or
// SIGINT once some frames are done (it writes the outputs of every finished frame and exits 143 / 130), or
// SIGKILL (the streamed trajectories hold every finished frame).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/glmbslam_process.hpp"
#include "app/pipeline/trajectory_stream_stage.hpp"
#include "core/interrupt.hpp"
#include "core/progress.hpp"
#include "io/trajectory_io.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kFrames = 60;

/// The rendered clip (cached between test processes like test_stereo_run's; render privately, then rename).
fs::path rendered_sequence() {
  const fs::path clip =
      fs::temp_directory_path() / ("glmbslam_test_interrupt_clip_" + std::to_string(kFrames));
  if (!fs::exists(clip / "poses" / "00.txt")) {
    ProgressReporter::set_enabled(false);
    const fs::path mine =
        fs::temp_directory_path() / ("glmbslam_test_interrupt_clip_" + std::to_string(getpid()));
    fs::remove_all(mine);
    sim::SequenceRenderOptions o;
    o.out_dir = mine.string();
    o.frames = "0:" + std::to_string(kFrames);
    sim::render_kitti_sequence(o);
    std::error_code ec;
    fs::rename(mine, clip, ec);
    if (ec) fs::remove_all(mine);
  }
  return clip / "sequences" / "00";
}

/// Complete lines (ending in '\n') of a file that may be growing.
std::size_t complete_lines(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::size_t n = 0;
  char c;
  while (in.get(c)) n += c == '\n' ? 1 : 0;
  return n;
}

std::size_t line_count(const fs::path& p) {
  return io::read_kitti_poses(p.string()).size();
}

/// Starts `glmbslam run` on the clip into `out` (with `extra` arguments); returns its pid.
pid_t start_run(const fs::path& out, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args{
      "--threads", "1",          "--log-level", "warn", "run", rendered_sequence().string(),
      "--out",     out.string(), "--particles", "5"};
  args.insert(args.end(), extra.begin(), extra.end());
  glmbslam::test::remove_after_test(out.string() + ".log");
  return glmbslam::test::start_glmbslam(args, out.string() + ".log");
}

/// Waits until the streamed trajectory holds at least `frames` lines (or the process ended); returns the
/// lines seen then.
std::size_t wait_for_frames(pid_t pid, const fs::path& out, std::size_t frames) {
  const fs::path streamed = out / kStreamedTrajectoryFile;
  for (int i = 0; i < 60000; ++i) {  // 10 min at most, for heavily loaded machines and sanitizer builds
    const std::size_t n = complete_lines(streamed);
    if (n >= frames) return n;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) {
      ADD_FAILURE() << "glmbslam ended before " << frames << " frames were streamed (status " << status
                    << ")";
      return n;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ADD_FAILURE() << "no progress";
  return 0;
}

/// Starts a run into `out`, sends `signal` once at least 5 frames are streamed; returns the wait status and
/// the frames streamed when the signal was sent.
std::pair<int, std::size_t> signal_run(const fs::path& out, int signal,
                                       const std::vector<std::string>& extra = {}) {
  const pid_t pid = start_run(out, extra);
  const std::size_t streamed = wait_for_frames(pid, out, 5);
  EXPECT_GE(streamed, 5u);
  EXPECT_EQ(kill(pid, signal), 0);
  return {glmbslam::test::wait_for(pid), streamed};
}

void expect_graceful_stop(int signal, int exit_code) {
  if (!fs::exists(glmbslam::test::glmbslam_binary())) GTEST_SKIP() << "glmbslam executable not built";
  const fs::path out = glmbslam::test::fresh_temp_dir("interrupt");
  const auto [status, streamed] = signal_run(out, signal);
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), exit_code);

  // Every frame finished before the signal is in the final files, and metrics.json parses and says so.
  const std::size_t frames = line_count(out / "trajectory.txt");
  EXPECT_GE(frames, streamed);
  EXPECT_EQ(line_count(out / "vo_trajectory.txt"), frames);
  std::ifstream in(out / "metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  EXPECT_EQ(m.at("frames").get<std::size_t>(), frames);
  EXPECT_EQ(m.at("frames_requested").get<std::size_t>(), kFrames);
  EXPECT_EQ(m.at("interrupted").get<bool>(), frames < kFrames);
  if (frames < kFrames) {
    EXPECT_EQ(m.at("last_frame_done").get<std::size_t>(), frames - 1);
  }
  EXPECT_TRUE(m.contains("slam")) << "evaluated against the ground truth of the frames done";
  for (const char* f : {"map.pcd", "config_used.yaml", "report.html", "plots/map_top.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  // The streamed files are gone once the final ones are written.
  EXPECT_FALSE(fs::exists(out / kStreamedTrajectoryFile));
  EXPECT_FALSE(fs::exists(out / kStreamedVoTrajectoryFile));
  fs::remove_all(out);
}

TEST(Interrupt, SigtermWritesEveryFinishedFrameAndExits143) {
  expect_graceful_stop(SIGTERM, 143);
}

TEST(Interrupt, SigintWritesEveryFinishedFrameAndExits130) {
  expect_graceful_stop(SIGINT, 130);
}

// With --refine ml an interruption during the frames skips the final pass (minutes on a long run, which a
// scheduler's time limit would not wait for): the refined outputs are the online windows' for the frames
// done.
TEST(Interrupt, AnInterruptedRefinedRunSkipsTheFinalPass) {
  if (!fs::exists(glmbslam::test::glmbslam_binary())) GTEST_SKIP() << "glmbslam executable not built";
  const fs::path out = glmbslam::test::fresh_temp_dir("interrupt_refine");
  const auto [status, streamed] = signal_run(out, SIGINT, {"--refine", "ml"});
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const std::size_t frames = line_count(out / "trajectory.txt");
  EXPECT_GE(frames, streamed);
  std::ifstream in(out / "metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  ASSERT_LT(frames, kFrames) << "the signal came after the last frame";  // 5 frames streamed, 55 to go
  EXPECT_TRUE(m.at("interrupted").get<bool>());
  EXPECT_EQ(line_count(out / "trajectory_refined.txt"), frames);
  EXPECT_TRUE(m.contains("refined"));
  EXPECT_FALSE(m.at("refinement").contains("final_ms")) << "the final pass ran after the interruption";
  fs::remove_all(out);
}

TEST(Interrupt, SigkillLeavesEveryFinishedFrameInTheStreamedTrajectories) {
  if (!fs::exists(glmbslam::test::glmbslam_binary())) GTEST_SKIP() << "glmbslam executable not built";
  const fs::path out = glmbslam::test::fresh_temp_dir("interrupt");
  const auto [status, streamed] = signal_run(out, SIGKILL);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGKILL);
  // Every line is a complete, valid KITTI pose; nothing claims to be final.
  const std::size_t slam = line_count(out / kStreamedTrajectoryFile);
  EXPECT_GE(slam, streamed);
  const std::size_t vo = line_count(out / kStreamedVoTrajectoryFile);
  EXPECT_TRUE(vo == slam || vo == slam + 1) << vo << " VO lines, " << slam << " SLAM lines";
  EXPECT_FALSE(fs::exists(out / "trajectory.txt"));
  EXPECT_FALSE(fs::exists(out / "metrics.json"));
  fs::remove_all(out);
}

TEST(Interrupt, FlagAndExitCodes) {
  clear_interrupt();
  EXPECT_FALSE(interrupt_requested());
  EXPECT_EQ(interrupt_exit_code(), 0);
  request_interrupt(SIGINT);
  request_interrupt(SIGTERM);  // the first one counts
  EXPECT_TRUE(interrupt_requested());
  EXPECT_EQ(interrupt_signal(), SIGINT);
  EXPECT_EQ(interrupt_exit_code(), 130);
  clear_interrupt();
  request_interrupt(SIGTERM);
  EXPECT_EQ(interrupt_exit_code(), 143);
  clear_interrupt();
}

}  // namespace
}  // namespace glmbslam::app
