// ProgressReporter when stderr is not a terminal (tests, CI logs, redirected output): plain log lines, the
// final line exactly once, nothing when disabled.
#include <memory>
#include <sstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "core/progress.hpp"

namespace glmbslam {
namespace {

/// Captures what the default spdlog logger writes while it lives.
class LogCapture {
 public:
  LogCapture() : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(text_);
    sink->set_pattern("%v");
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink));
  }
  ~LogCapture() { spdlog::set_default_logger(previous_); }
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::logger> previous_;
};

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t i = s.find(what); i != std::string::npos; i = s.find(what, i + 1)) ++n;
  return n;
}

TEST(ProgressReporter, FinalLineOnceWithItsExtraInfo) {
  if (::isatty(STDERR_FILENO)) GTEST_SKIP() << "stderr is a terminal: the bar is drawn instead of log lines";
  LogCapture capture;
  {
    ProgressReporter progress(3, "run");
    for (std::size_t k = 1; k <= 3; ++k) progress.update(k, "tracks " + std::to_string(10 * k));
    progress.finish();
  }
  const std::string text = capture.text();
  EXPECT_EQ(count(text, "run 3/3 (100%)"), 1u) << text;
  EXPECT_NE(text.find("run 3/3 (100%)"), std::string::npos);
  EXPECT_NE(text.find("tracks 30"), std::string::npos) << text;
  EXPECT_EQ(text.find("ETA 00:00 \n"), std::string::npos) << "no trailing blank: " << text;
}

TEST(ProgressReporter, FinishPrintsTheFinalLineWhenUpdatesStoppedShort) {
  if (::isatty(STDERR_FILENO)) GTEST_SKIP() << "stderr is a terminal: the bar is drawn instead of log lines";
  LogCapture capture;
  {
    ProgressReporter progress(5, "vo");
    progress.update(2);
    progress.finish("done");
  }
  EXPECT_EQ(count(capture.text(), "vo 5/5 (100%)"), 1u) << capture.text();
}

TEST(ProgressReporter, DisabledPrintsNothing) {
  LogCapture capture;
  ProgressReporter::set_enabled(false);
  {
    ProgressReporter progress(2, "sim");
    progress.update(1);
    progress.finish();
  }
  ProgressReporter::set_enabled(true);
  EXPECT_EQ(capture.text(), "");
}

}  // namespace
}  // namespace glmbslam
