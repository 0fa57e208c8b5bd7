// Opening LCM with liblcm's own reason for refusing a URL in Saccade's one-line error.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace lcm {
class LCM;
}

namespace saccade {

/// An LCM instance on `url`, or nullptr with one line in `error`: "cannot open LCM at 'URL':
/// liblcm's reason (a malformed URL, or no multicast route: see docs/LCM.md)". liblcm writes
/// that reason to stderr as a line of its own; it is taken from there into this one. While it
/// runs stderr goes to a pipe: a line another thread writes meanwhile (a signal's log line) is
/// printed after it, or folded into the reason when the URL is refused.
std::unique_ptr<lcm::LCM> OpenLcm(const std::string& url, std::string* error);

/// The datagrams the kernel has dropped, since they were opened, on this process's UDP sockets
/// bound to `url`'s port (udpm://, 7667 when the URL names none): what a full receive buffer
/// cost, a large message's fragments beyond `net.core.rmem_max` or a flood. Read from
/// /proc/net/udp and udp6 (the sockets matched by inode from /proc/self/fd); 0 for another
/// provider or when /proc cannot say.
std::int64_t LcmDatagramsDropped(const std::string& url);

}  // namespace saccade
