// Opening LCM with liblcm's own reason for refusing a URL in Saccade's one-line error.
#pragma once

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

}  // namespace saccade
