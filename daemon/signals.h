// Turns SIGINT, SIGTERM and SIGHUP into calls on an ordinary thread, so the handler may take
// locks and stop sources (a signal handler itself may do neither).
#pragma once

#include <atomic>
#include <functional>
#include <thread>

namespace saccade {

/// Blocks the three signals in the calling thread (construct it before starting threads, so
/// they inherit the mask) and runs `on_signal(signo)` on its own thread for each one that
/// arrives. The destructor stops that thread and restores the mask.
class SignalWaiter {
 public:
  explicit SignalWaiter(std::function<void(int)> on_signal);
  ~SignalWaiter();
  SignalWaiter(const SignalWaiter&) = delete;
  SignalWaiter& operator=(const SignalWaiter&) = delete;

 private:
  std::function<void(int)> on_signal_;
  std::atomic<bool> stopping_{false};  // set by the destructor before its SIGUSR2
  std::thread thread_;
};

}  // namespace saccade
