#include "core/progress.hpp"

#include <atomic>
#include <cstdio>

#include <unistd.h>

#include <spdlog/spdlog.h>

namespace glmbslam {
namespace {
std::atomic<bool> g_enabled{true};

std::string format_duration(double seconds) {
  if (seconds < 0 || seconds > 1e7) return "--:--";
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%02ld:%02ld", s / 60, s % 60);
  }
  return buf;
}
}  // namespace

void ProgressReporter::set_enabled(bool enabled) {
  g_enabled = enabled;
}

ProgressReporter::ProgressReporter(std::size_t total, std::string label)
    : total_(total),
      label_(std::move(label)),
      tty_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

ProgressReporter::~ProgressReporter() {
  if (!finished_ && tty_ && g_enabled) std::fputc('\n', stderr);
}

void ProgressReporter::update(std::size_t done, const std::string& extra) {
  if (!g_enabled) return;
  const auto now = std::chrono::steady_clock::now();
  const double since_print = std::chrono::duration<double>(now - last_print_).count();
  const bool last = done >= total_;
  if (last && printed_ >= total_) return;  // the final line is printed once
  if (!last && since_print < (tty_ ? 0.2 : 10.0)) return;
  print(done, extra);
}

void ProgressReporter::print(std::size_t done, const std::string& extra) {
  const auto now = std::chrono::steady_clock::now();
  last_print_ = now;
  printed_ = done;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total_ - std::min(done, total_)) / rate : -1.0;
  const double frac = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  char head[160];
  std::snprintf(head, sizeof head, "%s %zu/%zu (%.0f%%) %.1f/s ETA %s", label_.c_str(), done, total_,
                100.0 * frac, rate, format_duration(eta).c_str());
  if (tty_) {
    const int width = 24;
    const int filled = static_cast<int>(frac * width);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r[%s] %s%s%s\033[K", bar.c_str(), head, extra.empty() ? "" : " ", extra.c_str());
    std::fflush(stderr);
  } else if (extra.empty()) {
    spdlog::info("{}", head);
  } else {
    spdlog::info("{} {}", head, extra);
  }
}

void ProgressReporter::finish(const std::string& extra) {
  if (finished_) return;
  update(total_, extra);
  finished_ = true;
  if (tty_ && g_enabled) std::fputc('\n', stderr);
}

void ProgressReporter::finish_at(std::size_t done, const std::string& extra) {
  if (done >= total_) return finish(extra);
  if (finished_) return;
  if (g_enabled) print(done, extra);
  finished_ = true;
  if (tty_ && g_enabled) std::fputc('\n', stderr);
}

}  // namespace glmbslam
