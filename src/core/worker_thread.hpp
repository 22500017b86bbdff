#pragma once
// One persistent thread that runs submitted jobs in submission order, each result (or exception) delivered
// through a std::future. It replaces std::async(std::launch::async, ...) in per-frame code: std::async starts
// a new thread on every call, and libraries keep per-thread state for every thread that ever ran their code
// (OpenCV allocates thread-local buffers the first time a thread enters cv::parallel_for_, e.g. in
// cv::resize, and keeps them for the life of the process). One thread per frame therefore grew the memory of
// a long run by about 2.5 KiB per frame (20 000-frame soak, heaptrack); one persistent thread allocates them
// once.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>

namespace glmbslam {

class WorkerThread {
 public:
  WorkerThread() : thread_([this] { loop(); }) {}
  /// Runs the jobs already submitted, then joins the thread.
  ~WorkerThread() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  /// Queues `job` (callable with no arguments); the future holds its result or the exception it threw.
  template <class F>
  std::future<std::invoke_result_t<F>> submit(F&& job) {
    using R = std::invoke_result_t<F>;
    auto task = std::make_shared<std::packaged_task<R()>>(std::forward<F>(job));
    std::future<R> result = task->get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      jobs_.emplace_back([task] { (*task)(); });
    }
    wake_.notify_one();
    return result;
  }

  /// The id of the worker's thread (every job runs on it).
  std::thread::id id() const { return thread_.get_id(); }

 private:
  void loop() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
        if (jobs_.empty()) return;  // stopping, and every queued job has run
        job = std::move(jobs_.front());
        jobs_.pop_front();
      }
      job();  // a packaged_task: exceptions go to its future
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;  // last: started after the members it uses exist
};

}  // namespace glmbslam
