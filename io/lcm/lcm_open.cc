#include "io/lcm/lcm_open.h"

#include "core/fail.h"

#include <fcntl.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

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

namespace {

// The port of a udpm:// URL ("udpm://239.255.76.67:7667?ttl=0"), 7667 when it names none; 0
// for another provider.
unsigned UdpmPort(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return 0;
  const std::string address =
      url.substr(7, url.find('?') == std::string::npos ? std::string::npos : url.find('?') - 7);
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos) return 7667;
  const unsigned long port = std::strtoul(address.c_str() + colon + 1, nullptr, 10);
  return port > 0 && port < 65536 ? static_cast<unsigned>(port) : 0;
}

// The inodes of this process's sockets, from its /proc/self/fd links ("socket:[1234]").
std::set<std::string> SocketInodes() {
  std::set<std::string> inodes;
  std::error_code ec;
  for (std::filesystem::directory_iterator it("/proc/self/fd", ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string target = std::filesystem::read_symlink(it->path(), ec).string();
    if (!ec && target.rfind("socket:[", 0) == 0 && target.back() == ']')
      inodes.insert(target.substr(8, target.size() - 9));
    ec.clear();
  }
  return inodes;
}

}  // namespace

std::int64_t LcmDatagramsDropped(const std::string& url) {
  const unsigned port = UdpmPort(url);
  if (port == 0) return 0;
  const std::set<std::string> inodes = SocketInodes();
  char port_hex[8];
  std::snprintf(port_hex, sizeof port_hex, "%04X", port);
  std::int64_t dropped = 0;
  for (const char* table : {"/proc/net/udp", "/proc/net/udp6"}) {
    std::ifstream in(table);
    std::string line;
    std::getline(in, line);  // the header
    // sl local_address rem_address st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      std::string f[13];
      for (std::string& field : f) fields >> field;
      const std::size_t colon = f[1].rfind(':');
      if (f[12].empty() || colon == std::string::npos || f[1].substr(colon + 1) != port_hex ||
          inodes.count(f[9]) == 0)
        continue;
      dropped += std::strtoll(f[12].c_str(), nullptr, 10);
    }
  }
  return dropped;
}

}  // namespace saccade
