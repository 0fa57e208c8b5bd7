#include "io/lcm_open.h"

#include "core/fail.h"

#include <fcntl.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <cerrno>
#include <cstdio>

namespace saccade {

namespace {

// liblcm's lines ("Error: Bad multicast IP address ...") as one: "Error: " dropped, lines
// joined with "; ".
std::string Reason(const std::string& said) {
  std::string reason;
  std::size_t start = 0;
  while (start < said.size()) {
    std::size_t end = said.find('\n', start);
    if (end == std::string::npos) end = said.size();
    std::string line = said.substr(start, end - start);
    start = end + 1;
    if (line.rfind("Error: ", 0) == 0) line.erase(0, 7);
    if (line.empty()) continue;
    reason += (reason.empty() ? "" : "; ") + line;
  }
  return reason;
}

}  // namespace

std::unique_ptr<lcm::LCM> OpenLcm(const std::string& url, std::string* error) {
  // stderr points at a pipe while liblcm opens (non-blocking: past the pipe's 64 KB, what
  // liblcm writes is dropped rather than blocking it).
  int pipe_fds[2] = {-1, -1};
  const int saved = fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 0);
  const bool capture = saved >= 0 && pipe2(pipe_fds, O_NONBLOCK | O_CLOEXEC) == 0;
  if (capture) {
    std::fflush(stderr);
    dup2(pipe_fds[1], STDERR_FILENO);
  }
  auto lcm = std::make_unique<lcm::LCM>(url);
  std::string said;
  if (capture) {
    std::fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(pipe_fds[1]);
    char buffer[1024];
    ssize_t n;
    while ((n = read(pipe_fds[0], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR))
      if (n > 0) said.append(buffer, static_cast<std::size_t>(n));
    close(pipe_fds[0]);
  }
  if (saved >= 0) close(saved);
  // liblcm opens a URL whose options it cannot read ("ttl=abc", "foo=1") and only warns: the
  // option is silently dropped (a ttl of 0 or 1 instead of the one asked). Refused, as any
  // setting Saccade cannot honour.
  const bool option_ignored = said.find("Invalid value for ") != std::string::npos ||
                              said.find("unknown provider argument") != std::string::npos;
  if (lcm->good() && !option_ignored) {
    if (!said.empty()) std::fputs(said.c_str(), stderr);  // a warning on success goes on
    return lcm;
  }
  std::string reason = Reason(said);
  for (std::size_t at; (at = reason.find(" -- ")) != std::string::npos;) {
    const std::size_t from = reason.rfind("; ", at);  // "lcm_udpm.c:237 -- " is liblcm's own
    reason.erase(from == std::string::npos ? 0 : from + 2,
                 at + 4 - (from == std::string::npos ? 0 : from + 2));
  }
  if (reason.rfind("Warning: ", 0) == 0) reason.erase(0, 9);
  Fail(error, "cannot open LCM at '" + url + "'" + (reason.empty() ? "" : ": " + reason) +
                  " (a malformed URL, or no multicast route: see docs/LCM.md)");
  return nullptr;
}

}  // namespace saccade
