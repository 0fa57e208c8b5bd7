// `saccade view`: a small web server that listens to a saccaded over LCM and serves one live
// page (io/viewer/web/) and its data (docs/VIEWER.md). The state is kept here; viewer_http.cc
// serves it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace saccade {

struct ViewerOptions {
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  std::string channel_prefix = "SACCADE";
  std::string bind = "127.0.0.1";  // the address the page is served on (local by default)
  int port = 8080;
  std::string web_dir;       // the page's files (index.html, viewer.js, vendor/)
  double stale_after_s = 3;  // no message for this long: the page says no daemon is heard
  double history_s = 60;     // the strips' span
};

/// What the viewer has heard, thread-safe: fed with each message's bytes as LCM delivered
/// them (each decoded inside a guard; a malformed one is counted and dropped), read as JSON.
class ViewerState {
 public:
  ViewerState(const ViewerOptions& options);
  ~ViewerState();

  /// The channel's message; false when it did not decode (counted in the state's `rejected`).
  /// `now_s` is the viewer's steady clock.
  bool OnMessage(const std::string& channel, const void* data, std::size_t size, double now_s);

  /// GET /api/state: {"connected", "heard_s_ago", "lcm_url", "channel_prefix", "detections",
  /// "instances" (each with "centroid" and "confidence"), "fixation", "status", "trail",
  /// "history", "preview" (its frame's geometry and instances), "rejected"}.
  std::string StateJson(double now_s) const;
  /// The newest preview's JPEG and points block (io/lcm/preview.h); empty before the first, and
  /// when `seq` (>= 0) is not the newest's.
  std::vector<std::uint8_t> PreviewImage(std::int64_t seq) const;
  std::vector<std::uint8_t> PreviewPoints(std::int64_t seq) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The page's server and its LCM listener (viewer_http.cc).
class ViewerServer {
 public:
  /// Opens LCM at options.lcm_url, subscribes to the prefix's channels and binds the port.
  /// nullptr with one line in `error` when LCM, the address or the page's files fail.
  static std::unique_ptr<ViewerServer> Open(const ViewerOptions& options, std::string* error);
  virtual ~ViewerServer() = default;
  /// Where to point a browser: http://BIND:PORT/ (the actual port when options.port is 0).
  virtual std::string Url() const = 0;
  /// Serves and listens until Stop(); false with `error` when the server failed.
  virtual bool Run(std::string* error) = 0;
  /// Ends Run; from any thread, also before Run.
  virtual void Stop() = 0;
};

}  // namespace saccade
