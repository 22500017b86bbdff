#pragma once
// Progress reporting for long runs: a live bar on a terminal (frame, rate, extra info, ETA) redrawn at most
// 5 times a second, plain log lines every 10 s otherwise (so CI logs and redirected output stay readable).
// `glmbslam --quiet` disables it (set_enabled(false)).
#include <chrono>
#include <cstddef>
#include <string>

namespace glmbslam {

class ProgressReporter {
 public:
  /// `total` steps; `label` prefixes each line. Output goes to stderr.
  ProgressReporter(std::size_t total, std::string label);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// Reports that `done` steps are complete; `extra` (e.g. "landmarks 1234") is shown beside the rate.
  void update(std::size_t done, const std::string& extra = "");
  /// Ends the bar: prints the final line unless update() already printed it (then `extra` is ignored).
  void finish(const std::string& extra = "");
  /// Ends the bar at `done` of the total (a run stopped early): its final line says where it stopped.
  void finish_at(std::size_t done, const std::string& extra = "");

  /// Disables all output (for tests and quiet runs).
  static void set_enabled(bool enabled);

 private:
  void print(std::size_t done, const std::string& extra);

  std::size_t total_;
  std::string label_;
  bool tty_;
  bool finished_ = false;
  std::size_t printed_ = 0;  ///< `done` of the last line printed (an update at total_ prints once)
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace glmbslam
