// What the live camera sources (OpenNI2, libfreenect) share: frames, or an error, handed over
// from a driver's thread through a latest-frame mailbox; a Stop() that wakes every wait; the
// counters and the state that SourceStats reports.
#pragma once

#include "io/sources/frame_source.h"
#include "io/sources/mailbox.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>

namespace saccade {

class CameraSource : public FrameSource {
 public:
  /// The next item of the mailbox: a frame, the error it carries, or the end once closed.
  Status Next(Frame* frame, std::string* error) override;
  /// Closes the mailbox and wakes whatever waits on wake_ (a watchdog's sleep, a back-off).
  void Stop() override;

 protected:
  struct Item {
    bool ok = true;
    Frame frame;
    std::string error;
  };

  /// produced, dropped (by the mailbox), reconnects and the state; a source adds its own.
  SourceStats BaseStats() const;
  void SetState(const std::string& state);
  /// An item that ends the source with `error` (Next() returns it, then the end).
  void PostError(const std::string& error);
  /// At open, a device that is not there (`why`): false when the source may not wait
  /// (`wait_at_start_s` 0); else the state says so and the wait is bounded by it.
  bool StartWaiting(const std::string& why, double wait_at_start_s);
  /// After a failed attempt to connect (`why`): when waiting at start and its time is over,
  /// ends the source with why and how long it waited, and returns false; else says why in the
  /// state ("waiting for device: " or "reconnecting: "), sleeps `*backoff` (woken by Stop())
  /// and doubles it up to 8 s. `lock` holds wake_mutex_.
  bool BackOff(bool waiting, const std::string& why, std::chrono::milliseconds* backoff,
               std::unique_lock<std::mutex>* lock);

  LatestMailbox<Item> mailbox_;
  std::atomic<bool> stopped_{false};
  std::atomic<std::uint64_t> produced_{0}, reconnects_{0};
  // Sleeps that Stop() must end: wait on wake_ with wake_mutex_, for stopped_.
  std::mutex wake_mutex_;
  std::condition_variable wake_;

 private:
  const std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point waiting_until_;
  mutable std::mutex state_mutex_;
  std::string state_ = "streaming";
};

}  // namespace saccade
