// `saccade view`: the live web viewer (io/viewer/viewer.h, docs/VIEWER.md).
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/signals.h"
#include "io/lcm/bus.h"
#include "io/viewer/viewer.h"

#include <signal.h>

#include <filesystem>
#include <mutex>
#include <ostream>

namespace saccade {
namespace {

// The page's files: installed beside the binary (PREFIX/bin/saccade finds
// PREFIX/share/saccade/web, whatever the prefix), else the build tree's (the `web` target).
std::string DefaultWebDir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const auto installed = exe.parent_path().parent_path() / "share" / "saccade" / "web";
    if (std::filesystem::is_regular_file(installed / "index.html", ec)) return installed.string();
  }
  return SACCADE_BUILD_WEB_DIR;
}

}  // namespace

int RunView(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  const ViewerOptions defaults;
  Args args("saccade view",
            "Serves a live page of what saccaded sees: the camera image with the fovea's "
            "boxes and every instance, an orbitable 3D view of the foveated cloud, and a "
            "minute of fps, drops, latency, G and mode. Runs until SIGINT. saccaded's "
            "preview channel (preview.enabled in its config) gives it the image and points.");
  args.Value("lcm-url", "URL",
             "the LCM network saccaded publishes on (default: " + defaults.lcm_url + ")")
      .Value("prefix", "NAME",
             "saccaded's channel prefix (default: " + defaults.channel_prefix + ")")
      .Value("port", "N", "the port to serve on; 0 picks a free one (default: 8080)")
      .Value("bind", "ADDRESS",
             "the address to serve on; 0.0.0.0 for every interface (default: 127.0.0.1, this "
             "machine only)")
      .Value("web-dir", "DIR", "the page's files (default: the installed or built ones)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  ViewerOptions options;
  options.lcm_url = args.Get("lcm-url", defaults.lcm_url);
  options.channel_prefix = args.Get("prefix", defaults.channel_prefix);
  options.bind = args.Get("bind", defaults.bind);
  options.web_dir = args.Has("web-dir") ? args.Get("web-dir") : DefaultWebDir();
  if (args.Has("port")) {
    const auto port = Args::ParseNumber(args.Get("port"));
    if (!port || *port < 0 || *port > 65535 || *port != static_cast<int>(*port))
      return Usage(err, "view", "--port must be a whole number in [0, 65535]");
    options.port = static_cast<int>(*port);
  }
  BusOptions bus;
  bus.channel_prefix = options.channel_prefix;
  std::string error;
  if (!bus.IsValid(&error)) return Usage(err, "view", "--prefix: " + error);

  std::mutex server_mutex;
  ViewerServer* running = nullptr;
  bool stop_requested = false;
  SignalWaiter signals([&](int signo) {
    if (signo == SIGHUP) return;
    std::lock_guard<std::mutex> lock(server_mutex);
    stop_requested = true;
    if (running) running->Stop();
  });
  std::unique_ptr<ViewerServer> server = ViewerServer::Open(options, &error);
  if (!server) {
    err << error << "\n";
    return kExitFailure;
  }
  {
    std::lock_guard<std::mutex> lock(server_mutex);
    running = server.get();
    if (stop_requested) server->Stop();
  }
  out << "saccade view: open " << server->Url() << " (listening to " << options.channel_prefix
      << "_* on " << options.lcm_url << "; Ctrl-C stops)" << std::endl;
  const bool ok = server->Run(&error);
  {
    std::lock_guard<std::mutex> lock(server_mutex);
    running = nullptr;
  }
  if (!ok) {
    err << error << "\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace saccade
