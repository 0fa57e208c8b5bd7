#include "daemon/notify.h"

#include <systemd/sd-daemon.h>

namespace saccade {

bool SystemdNotify(const std::string& state) { return sd_notify(0, state.c_str()) >= 0; }

SystemdWatchdog::SystemdWatchdog() {
  std::uint64_t usec = 0;
  // sd_watchdog_enabled checks $WATCHDOG_PID against this process: a child of the service
  // that inherited the variables does not ping for it.
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0)
    interval_ = std::chrono::duration_cast<Clock::duration>(std::chrono::microseconds(usec / 2));
  last_ping_ = Clock::now();
}

bool SystemdWatchdog::Beat(bool progressing, Clock::time_point now) {
  if (!Enabled()) return false;
  progressed_ = progressed_ || progressing;
  if (!progressed_ || now - last_ping_ < interval_) return false;
  sd_notify(0, "WATCHDOG=1");
  last_ping_ = now;
  progressed_ = false;
  return true;
}

}  // namespace saccade
