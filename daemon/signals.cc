#include "daemon/signals.h"

#include <pthread.h>
#include <signal.h>

namespace saccade {

namespace {

// The signals handled, and SIGUSR2: the destructor's wake-up call to the waiting thread.
sigset_t Handled() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  sigaddset(&set, SIGUSR2);
  return set;
}

}  // namespace

SignalWaiter::SignalWaiter(std::function<void(int)> on_signal) : on_signal_(std::move(on_signal)) {
  const sigset_t set = Handled();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  thread_ = std::thread([this] {
    const sigset_t wait_set = Handled();
    for (;;) {
      int signo = 0;
      if (sigwait(&wait_set, &signo) != 0) continue;
      // SIGUSR2 from our destructor ends the wait; one from outside is ignored (it once ended
      // the wait, and with it the handling of SIGTERM, SIGINT and SIGHUP).
      if (signo == SIGUSR2) {
        if (stopping_) return;
        continue;
      }
      on_signal_(signo);
    }
  });
}

SignalWaiter::~SignalWaiter() {
  stopping_ = true;
  pthread_kill(thread_.native_handle(), SIGUSR2);
  thread_.join();
  const sigset_t set = Handled();
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
}

}  // namespace saccade
