// The viewer's HTTP side (cpp-httplib, kept to this one translation unit) and its LCM
// listener: the page's files from options.web_dir, and its data under /api/.
#include "io/viewer/viewer.h"

#include "core/fail.h"
#include "io/base/clock.h"
#include "io/lcm/bus.h"
#include "io/lcm/lcm_open.h"

#include <httplib.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <filesystem>
#include <thread>

namespace saccade {
namespace {

double SteadyNowS() { return static_cast<double>(SteadyNowNs()) * 1e-9; }

/// LCM takes a channel as a regular expression: this one matches `channel` alone.
std::string Literal(const std::string& channel) {
  std::string out;
  for (const char c : channel) {
    if (std::string("\\^$.|?*+()[]{}").find(c) != std::string::npos) out += '\\';
    out += c;
  }
  return out;
}

/// The sequence number a client asks for (?seq=N), -1 for the newest.
std::int64_t SeqOf(const httplib::Request& request) {
  if (!request.has_param("seq")) return -1;
  const std::string text = request.get_param_value("seq");
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  return end && *end == '\0' && !text.empty() && v >= 0 ? v : -1;
}

class HttpViewer : public ViewerServer {
 public:
  HttpViewer(const ViewerOptions& options, std::unique_ptr<lcm::LCM> lcm)
      : options_(options), state_(options), lcm_(std::move(lcm)) {}

  ~HttpViewer() override {
    Stop();
    if (listener_.joinable()) listener_.join();
    for (int fd : wake_)
      if (fd >= 0) close(fd);
  }

  bool Start(std::string* error) {
    if (pipe(wake_) != 0) return Fail(error, "saccade view: cannot create a pipe");
    for (const std::string& channel :
         {DetectionsChannel(options_.channel_prefix), FixationChannel(options_.channel_prefix),
          StatusChannel(options_.channel_prefix), PreviewChannel(options_.channel_prefix)})
      lcm_->subscribeFunction(Literal(channel), &HttpViewer::OnLcm, this);
    Routes();
    // httplib's default also sets SO_REUSEPORT, with which a second viewer would share the
    // port silently: a restart may reuse it at once, a second server may not.
    server_.set_socket_options([](int sock) {
      const int yes = 1;
      setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    port_ = options_.port == 0
                ? server_.bind_to_any_port(options_.bind)
                : (server_.bind_to_port(options_.bind, options_.port) ? options_.port : -1);
    if (port_ < 0)
      return Fail(error, "saccade view: cannot listen on " + options_.bind + ":" +
                             std::to_string(options_.port) +
                             " (in use, or not an address of this machine; --port, --bind)");
    listener_ = std::thread([this] { Listen(); });
    return true;
  }

  std::string Url() const override {
    const bool v6 = options_.bind.find(':') != std::string::npos;
    return "http://" + (v6 ? "[" + options_.bind + "]" : options_.bind) + ":" +
           std::to_string(port_) + "/";
  }

  bool Run(std::string* error) override {
    in_run_ = true;
    const bool ok = stopped_ || server_.listen_after_bind() || stopped_;
    in_run_ = false;
    return ok ? true : Fail(error, "saccade view: the web server stopped unexpectedly");
  }

  void Stop() override {
    if (stopped_.exchange(true)) return;
    if (wake_[1] >= 0) {
      const char byte = 0;
      [[maybe_unused]] const auto n = write(wake_[1], &byte, 1);
    }
    // httplib's stop() does nothing until the server is running: a Stop that comes while Run
    // is starting to listen repeats it until Run has returned.
    while (in_run_) {
      server_.stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

 private:
  static void OnLcm(const lcm::ReceiveBuffer* buffer, const std::string& channel,
                    HttpViewer* self) {
    self->state_.OnMessage(channel, buffer->data, buffer->data_size, SteadyNowS());
  }

  // LCM's messages, until Stop.
  void Listen() {
    pollfd fds[2] = {{lcm_->getFileno(), POLLIN, 0}, {wake_[0], POLLIN, 0}};
    while (!stopped_) {
      if (poll(fds, 2, -1) < 0) continue;  // EINTR
      if (fds[0].revents & (POLLERR | POLLHUP | POLLNVAL)) return;
      if (fds[0].revents & POLLIN) lcm_->handle();
    }
  }

  void Routes() {
    server_.set_mount_point("/", options_.web_dir);
    server_.Get("/api/state", [this](const httplib::Request&, httplib::Response& r) {
      r.set_header("Cache-Control", "no-store");
      r.set_content(state_.StateJson(SteadyNowS()), "application/json");
    });
    const auto binary = [this](bool image) {
      return [this, image](const httplib::Request& request, httplib::Response& r) {
        const std::vector<std::uint8_t> bytes =
            image ? state_.PreviewImage(SeqOf(request)) : state_.PreviewPoints(SeqOf(request));
        if (bytes.empty()) {
          r.status = 404;
          r.set_content(image ? "no preview yet (is preview.enabled on in saccaded's config?)"
                              : "no preview of that frame",
                        "text/plain");
          return;
        }
        r.set_header("Cache-Control", "no-store");
        r.set_content(reinterpret_cast<const char*>(bytes.data()), bytes.size(),
                      image ? "image/jpeg" : "application/octet-stream");
      };
    };
    server_.Get("/api/preview.jpg", binary(true));
    server_.Get("/api/points.bin", binary(false));
  }

  const ViewerOptions options_;
  ViewerState state_;
  std::unique_ptr<lcm::LCM> lcm_;
  httplib::Server server_;
  int port_ = -1;
  int wake_[2] = {-1, -1};
  std::atomic<bool> stopped_{false};
  std::atomic<bool> in_run_{false};  // Run is listening, or about to
  std::thread listener_;
};

}  // namespace

std::unique_ptr<ViewerServer> ViewerServer::Open(const ViewerOptions& options, std::string* error) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(std::filesystem::path(options.web_dir) / "index.html",
                                        ec)) {
    Fail(error, "saccade view: the page's files are not in '" + options.web_dir +
                    "' (no index.html; --web-dir, or build the 'web' target)");
    return nullptr;
  }
  std::string why;
  std::unique_ptr<lcm::LCM> lcm = OpenLcm(options.lcm_url, &why);
  if (!lcm) {
    Fail(error, "saccade view: " + why);
    return nullptr;
  }
  auto viewer = std::make_unique<HttpViewer>(options, std::move(lcm));
  if (!viewer->Start(error)) return nullptr;
  return viewer;
}

}  // namespace saccade
