// saccaded's engine: frames from a source through foveation and recognition (in parallel),
// attention and publishing (serial, in frame order) in a tbb::parallel_pipeline with a bounded
// number of frames in flight, plus the 1 Hz status and the commands from the bus.
#pragma once

#include "daemon/settings.h"

#include <functional>
#include <memory>
#include <string>

namespace saccade {

class Tracker {
 public:
  /// Called on the status thread each period: `progressing` is true when a frame went through
  /// the pipeline since the last call, or the pipeline is waiting for a reason it knows (paused,
  /// a source reconnecting). saccaded kicks the systemd watchdog from here.
  using Heartbeat = std::function<void(bool progressing)>;

  /// Opens the source and the bus and describes the models. nullptr with one line in `error`
  /// (the source, a model or LCM) when it cannot.
  static std::unique_ptr<Tracker> Create(const DaemonSettings& settings, Heartbeat heartbeat,
                                         std::string* error);
  ~Tracker();

  /// Runs until the source ends or Stop(); every frame taken from the source is published
  /// before it returns. Returns false with `error` when the source failed.
  bool Run(std::string* error);
  /// Ends Run() after the frames in flight. Safe from any thread.
  void Stop();
  /// Applies new settings to a running tracker: recognition, fovea, attention, saliency and the
  /// models take effect on the next frame; source, LCM and pipeline settings need a restart and
  /// are reported as such. False with `error` (and nothing changed) when the models fail.
  bool Reload(const DaemonSettings& settings, std::string* error);

 private:
  struct State;
  explicit Tracker(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace saccade
