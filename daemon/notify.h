// systemd's notify protocol through libsystemd's sd_notify: the service's state (READY,
// RELOADING, STOPPING, STATUS) and the watchdog's pings. Outside systemd (no $NOTIFY_SOCKET)
// every call does nothing.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace saccade {

/// Sends `state` ("READY=1", "RELOADING=1", "STOPPING=1", "STATUS=..."). False when systemd
/// asked for notifications and the message could not be sent.
bool SystemdNotify(const std::string& state);

/// The watchdog systemd asked this process for ($WATCHDOG_USEC, when $WATCHDOG_PID is unset or
/// names this process): pings at half its timeout, as sd_watchdog_enabled(3) advises, and only
/// while the service makes progress, so that a wedged pipeline is restarted.
class SystemdWatchdog {
 public:
  using Clock = std::chrono::steady_clock;
  /// Reads the environment; Enabled() is false when systemd asked for no watchdog.
  SystemdWatchdog();
  bool Enabled() const { return interval_.count() > 0; }
  /// The time between pings: half the timeout.
  Clock::duration Interval() const { return interval_; }
  /// Called often (every few hundred ms): `progressing` says whether the service made progress
  /// since the last call. Pings when an interval has passed since the last ping and there was
  /// progress since. Returns true when it pinged.
  bool Beat(bool progressing, Clock::time_point now = Clock::now());

 private:
  Clock::duration interval_{0};
  Clock::time_point last_ping_{};
  bool progressed_ = false;
};

}  // namespace saccade
