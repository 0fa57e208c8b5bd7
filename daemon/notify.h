// systemd's notify protocol, written by hand (no libsystemd): one datagram per state change
// to the socket named by $NOTIFY_SOCKET. Without that variable every call does nothing.
#pragma once

#include <string>

namespace saccade {

/// Sends `state` ("READY=1", "WATCHDOG=1", "RELOADING=1", "STOPPING=1", "STATUS=...").
/// Returns false when NOTIFY_SOCKET is set but the message could not be sent.
bool SystemdNotify(const std::string& state);

/// True when systemd asked for watchdog pings ($WATCHDOG_USEC is set).
bool SystemdWatchdogEnabled();

}  // namespace saccade
