// saccaded's engine: frames from a source through foveation and recognition (in parallel; only
// when the tracks need it), tracking, attention and publishing (serial, in frame order) in a
// tbb::parallel_pipeline with a bounded number of frames in flight, plus the status and the
// commands from the bus. It is built from the stages of daemon/stages.h and takes its source and
// bus from outside, so a test can drive it frame by frame with an in-memory bus.
#pragma once

#include "daemon/settings.h"
#include "io/lcm/bus.h"
#include "io/sources/frame_source.h"

#include <functional>
#include <memory>
#include <string>

namespace saccade {

class Tracker {
 public:
  /// Called on the status thread every kHeartbeatPeriod (or status period, when shorter):
  /// `progressing` is true when a frame went through the pipeline since the last call, or the
  /// pipeline is waiting for a reason it knows (paused, a source reconnecting); `status` is the
  /// status just published, or null when none was this time. saccaded pings the systemd
  /// watchdog and sets the service's STATUS from here.
  using Heartbeat = std::function<void(bool progressing, const StatusReport* status)>;
  static constexpr double kHeartbeatPeriod = 0.25;  // seconds
  /// A reload's outcome, called on the tracker's control thread.
  using Done = std::function<void(bool ok, const std::string& error)>;

  /// Describes the models and subscribes to the bus's commands. The tracker owns `source` and
  /// `bus`; `source` may be null for a tracker driven by Process() alone (tests, bench-track).
  /// nullptr with one line in `error` when a model fails.
  static std::unique_ptr<Tracker> Create(const DaemonSettings& settings,
                                         std::unique_ptr<FrameSource> source,
                                         std::unique_ptr<Bus> bus, Heartbeat heartbeat,
                                         std::string* error);
  /// Describes the models, then opens the LCM bus and the source the settings name (in that
  /// order: a bad model is reported before a missing camera). nullptr with one line in `error`
  /// when one of them fails.
  static std::unique_ptr<Tracker> Open(const DaemonSettings& settings, Heartbeat heartbeat,
                                       std::string* error);
  ~Tracker();

  /// Runs until the source ends or Stop(); every frame taken from the source is published
  /// before it returns. Returns false with `error` when the source failed.
  bool Run(std::string* error);
  /// The run's last word, after Run: "stopped", and with ground truth how well the target was
  /// tracked and how many frames the source's rate made it drop.
  std::string ClosingLine() const;
  /// Takes one frame through recognition, attention and publishing on the calling thread, as
  /// Run does with each frame: for tests that drive the tracker frame by frame. Not while Run
  /// runs.
  void Process(Frame frame);
  /// Ends Run() after the frames in flight. Safe from any thread.
  void Stop();
  /// Applies new settings on the control thread (models are described there, not on the
  /// caller's): recognition, fovea, attention, saliency and the models take effect on the next
  /// frame after; source, LCM and pipeline settings need a restart and are reported as such.
  /// `done` gets false with the reason (and nothing changed) when the models fail.
  void Reload(const DaemonSettings& settings, Done done);
  /// Blocks until the reloads and model switches asked for so far have been applied.
  void WaitForControl();

 private:
  struct Impl;
  explicit Tracker(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace saccade
