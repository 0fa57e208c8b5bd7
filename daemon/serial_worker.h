// One thread that runs posted tasks in order: the tracker's control thread, where model
// switches and reloads (seconds of model description) run instead of on the LCM receiver's or
// the signal waiter's thread.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace saccade {

class SerialWorker {
 public:
  SerialWorker() : thread_([this] { Loop(); }) {}
  ~SerialWorker() { Stop(); }
  SerialWorker(const SerialWorker&) = delete;
  SerialWorker& operator=(const SerialWorker&) = delete;

  /// Queues `task` after those posted before it. False (and the task dropped) after Stop().
  /// Thread-safe.
  bool Post(std::function<void()> task) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return false;
    tasks_.push_back(std::move(task));
    cv_.notify_one();
    return true;
  }
  /// Blocks until every task posted before the call has run (at once after Stop()).
  void Flush() {
    std::mutex m;
    std::condition_variable done_cv;
    bool done = false;
    if (!Post([&] {
          std::lock_guard<std::mutex> lock(m);
          done = true;
          done_cv.notify_one();
        }))
      return;
    std::unique_lock<std::mutex> lock(m);
    done_cv.wait(lock, [&] { return done; });
  }
  /// Runs what is queued, then ends the thread; later posts are refused. Idempotent; not from a
  /// task.
  void Stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      cv_.notify_one();
    }
    if (thread_.joinable()) thread_.join();
  }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      cv_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
      if (tasks_.empty()) return;  // stopping, and nothing left to run
      std::function<void()> task = std::move(tasks_.front());
      tasks_.pop_front();
      lock.unlock();
      task();
      lock.lock();
    }
  }

  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> tasks_;  // guarded by mutex_
  bool stopping_ = false;                    // guarded by mutex_
  std::thread thread_;                       // last: starts after the members it uses
};

}  // namespace saccade
