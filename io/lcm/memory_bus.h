// A Bus that keeps what is published in memory and takes commands from a call: how a test
// drives the tracker frame by frame with no process and no socket. The LCM path has its own
// tests (tests/io/bus_test.cc, tests/daemon/saccaded_test.cc).
#pragma once

#include "io/lcm/bus.h"

#include <cstdint>
#include <mutex>
#include <vector>

namespace saccade {

/// Thread-safe: the tracker publishes from its stages while a test reads.
class MemoryBus : public Bus {
 public:
  struct Published {
    FrameDetections frame;
    Fixation fixation;
  };

  bool Publish(const FrameDetections& frame, const Fixation& fixation) override;
  bool PublishStatus(const StatusReport& status) override;
  bool PublishPreview(const Preview& preview, std::int64_t arrival_steady_ns,
                      const PreviewOptions& options, std::string* error) override;
  void Subscribe(CommandHandler handler) override;
  std::int64_t AcceptedCommands() const override;
  std::int64_t RejectedCommands() const override;
  std::string Describe() const override { return "memory"; }

  /// Hands `command` to the subscriber as the LCM bus would after decoding it; the verdict is
  /// counted when the subscriber replies (at once, or later from its own thread). False when
  /// nothing has subscribed.
  bool Send(const Command& command);
  /// Copies of what has been published so far, in order.
  std::vector<Published> Frames() const;
  std::vector<StatusReport> Statuses() const;
  std::vector<Preview> Previews() const;

 private:
  mutable std::mutex mutex_;
  CommandHandler handler_;                    // guarded by mutex_
  std::vector<Published> frames_;             // guarded by mutex_
  std::vector<StatusReport> statuses_;        // guarded by mutex_
  std::vector<Preview> previews_;             // guarded by mutex_
  std::int64_t accepted_ = 0, rejected_ = 0;  // guarded by mutex_
};

}  // namespace saccade
