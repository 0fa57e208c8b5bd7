// saccaded: the tracking service. Frames in, detections and fixations out over LCM.

#include "core/fail.h"
#include "core/fixation.h"
#include "daemon/args.h"
#include "daemon/exit_codes.h"
#include "daemon/notify.h"
#include "daemon/settings.h"
#include "daemon/signals.h"
#include "daemon/tracker.h"
#include "io/base/log.h"

#include <signal.h>
#include <unistd.h>
#include <csignal>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <mutex>

namespace {

constexpr const char* kAbout =
    "Tracks a known object in a depth stream and publishes, per frame, its detections and the "
    "attention loop's fixation over LCM (docs/LCM.md). Without --config Saccade's defaults "
    "apply (configs/saccaded.yaml writes them out, configs/paper.yaml holds the paper's); the "
    "flags override the file.";
constexpr const char* kFooter =
    R"(signals: SIGTERM/SIGINT finish the frames in flight and exit 0; SIGHUP reloads the config
file (a bad one is reported and the running one kept).

exit codes: 0 stopped cleanly or the source ended, 1 the source, a model or LCM failed,
            2 bad usage or configuration)";

// systemctl status's one line: what the pipeline does, how fast, what it lost.
std::string ServiceStatus(const saccade::StatusReport& s) {
  char counts[160];
  std::snprintf(counts, sizeof counts, ", %.1f fps, %lld dropped, %lld skipped, %lld unsent", s.fps,
                static_cast<long long>(s.frames_dropped), static_cast<long long>(s.frames_skipped),
                static_cast<long long>(s.frames_unsent));
  std::string line = s.paused ? "paused" : saccade::ModeName(s.mode);
  std::transform(line.begin(), line.end(), line.begin(), [](char c) {
    return c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  });
  line += counts;
  if (s.source_state != "streaming") line += "; source " + s.source_state;
  return line;
}

// The file, then the flags over it.
bool LoadSettings(const saccade::Args& args, saccade::DaemonSettings* settings,
                  std::string* error) {
  saccade::DaemonSettings s;  // Saccade's defaults; the file overrides them
  if (args.Has("config") && !saccade::LoadDaemonSettings(args.Get("config"), &s, error))
    return false;
  if (args.Has("source")) s.source.spec = args.Get("source");
  if (args.Has("model")) s.models = {args.Get("model")};
  if (args.Has("lcm-url")) s.bus.url = args.Get("lcm-url");
  if (args.Has("ros2")) s.ros2.enabled = true;
  if (s.models.empty()) {
    return saccade::Fail(error, "no model: set 'model' in the config file or pass --model");
  }
  if (!s.IsValid(error)) return false;
  // A person at a terminal sees a line a second; a service's log and a pipe do not.
  if (s.service.summary == saccade::ServiceOptions::Summary::kAuto)
    s.service.summary = isatty(STDOUT_FILENO) && !args.Has("quiet")
                            ? saccade::ServiceOptions::Summary::kLine
                            : saccade::ServiceOptions::Summary::kOff;
  *settings = s;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace saccade;
  // A reader of stdout or stderr that goes away (a closed pipe) must not end the daemon: the
  // write fails instead.
  std::signal(SIGPIPE, SIG_IGN);
  const std::vector<std::string> argv_list(argv + 1, argv + argc);
  Args args("saccaded", kAbout);
  args.Value("config", "FILE.yaml", "the settings file; every key is in configs/saccaded.yaml")
      .Value("source", "SPEC",
             "where frames come from, over the file's 'source' (see saccade "
             "record --help; docs/SOURCES.md)")
      .Value("model", "M.pcd", "the object's model, over the file's 'model'")
      .Value("lcm-url", "URL", "the LCM network, over the file's 'lcm.url'")
      .Switch("quiet", "no status line a second on a terminal (service.summary: auto)");
  if (Ros2Built())  // a build without Cyclone DDS has no ROS 2
    args.Switch("ros2",
                "also publish on ROS 2's wire (Cyclone DDS): detections, fixation, diagnostics "
                "(docs/ROS2.md; ros2.enabled)");
  args.Footer(kFooter);
  if (auto code = args.Parse(argv_list, std::cout, std::cerr)) return *code;
  std::string error;
  DaemonSettings settings;
  if (!LoadSettings(args, &settings, &error)) {
    std::cerr << "saccaded: error: " << error << "\n";
    return kExitUsage;
  }
  ConfigureLog("saccaded", settings.service.log_level);

  // Signals are turned into calls here before any thread starts, so every thread inherits
  // the mask and only the waiter's thread sees them.
  std::mutex tracker_mutex;
  Tracker* tracker = nullptr;  // guarded by tracker_mutex
  bool stop_requested = false;
  SignalWaiter signals([&](int signo) {
    std::lock_guard<std::mutex> lock(tracker_mutex);
    if (signo == SIGHUP) {
      if (!tracker) return;
      SystemdNotify("RELOADING=1");
      DaemonSettings next;
      std::string why;
      if (!LoadSettings(args, &next, &why)) {
        Log(LogLevel::kError, "reload failed, keeping the running configuration: " + why);
        SystemdNotify("READY=1");
        return;
      }
      // The models are described on the tracker's control thread; this thread stays free for
      // the next signal.
      tracker->Reload(
          next, [what = args.Get("config", "the defaults")](bool ok, const std::string& e) {
            if (ok)
              Log(LogLevel::kInfo, "reloaded " + what);
            else
              Log(LogLevel::kError, "reload failed, keeping the running configuration: " + e);
            SystemdNotify("READY=1");
          });
      return;
    }
    Log(LogLevel::kInfo, std::string("signal ") + (signo == SIGINT ? "SIGINT" : "SIGTERM") +
                             ": finishing the frames in flight");
    SystemdNotify("STOPPING=1");
    stop_requested = true;
    if (tracker) tracker->Stop();
  });

  SystemdWatchdog watchdog;
  if (watchdog.Enabled()) {
    char every[32];
    std::snprintf(every, sizeof every, "%g",
                  std::chrono::duration<double>(watchdog.Interval()).count());
    Log(LogLevel::kInfo, std::string("systemd watchdog: pinged every ") + every +
                             " s (half its timeout) while frames flow");
  }
  auto created = Tracker::Open(
      settings,
      [&watchdog](bool progressing, const StatusReport* status) {
        watchdog.Beat(progressing);
        if (status) SystemdNotify("STATUS=" + ServiceStatus(*status));
      },
      &error);
  if (!created) {
    Log(LogLevel::kError, error);
    return kExitFailure;
  }
  {
    std::lock_guard<std::mutex> lock(tracker_mutex);
    tracker = created.get();
    if (stop_requested) tracker->Stop();
  }
  SystemdNotify("READY=1");
  const bool ok = created->Run(&error);
  {
    std::lock_guard<std::mutex> lock(tracker_mutex);
    tracker = nullptr;
  }
  if (!ok) {
    Log(LogLevel::kError, error);
    return kExitFailure;
  }
  Log(LogLevel::kInfo, created->ClosingLine());
  return kExitOk;
}
