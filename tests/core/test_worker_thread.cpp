#include "core/worker_thread.hpp"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace glmbslam {
namespace {

TEST(WorkerThread, RunsEveryJobInOrderOnOneThread) {
  WorkerThread worker;
  std::vector<int> order;
  std::vector<std::future<std::thread::id>> ids;
  for (int i = 0; i < 200; ++i) {
    ids.push_back(worker.submit([&order, i] {
      order.push_back(i);  // only the worker touches it
      return std::this_thread::get_id();
    }));
  }
  for (auto& f : ids) EXPECT_EQ(f.get(), worker.id());
  ASSERT_EQ(order.size(), 200u);
  for (int i = 0; i < 200; ++i) EXPECT_EQ(order[static_cast<std::size_t>(i)], i);
  EXPECT_NE(worker.id(), std::this_thread::get_id());
}

TEST(WorkerThread, ReturnsResultsAndPassesExceptionsThroughTheFuture) {
  WorkerThread worker;
  auto ok = worker.submit([] { return 42; });
  auto bad = worker.submit([]() -> int { throw std::runtime_error("job failed"); });
  auto after = worker.submit([] { return 7; });
  EXPECT_EQ(ok.get(), 42);
  EXPECT_THROW(bad.get(), std::runtime_error);
  EXPECT_EQ(after.get(), 7);  // the worker survives a throwing job
}

TEST(WorkerThread, DestructorRunsTheJobsAlreadySubmitted) {
  std::atomic<int> done{0};
  {
    WorkerThread worker;
    for (int i = 0; i < 20; ++i) {
      (void)worker.submit([&done] {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ++done;
      });
    }
  }
  EXPECT_EQ(done.load(), 20);
}

}  // namespace
}  // namespace glmbslam
