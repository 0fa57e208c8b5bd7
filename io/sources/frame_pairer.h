// Pairs a sensor's depth frames with its colour frames by timestamp, for sources whose two
// streams come on their own threads or clocks (OpenNI2, libfreenect).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <utility>

namespace saccade {

/// A depth frame takes the colour frame nearest in time within `tolerance` (in the streams'
/// time unit) among those already come. It waits for that colour frame while at most `kMaxWaiting`
/// depth frames wait, and no longer once the colour stream has passed its time. Depth frames are
/// delivered in their order, each with its colour frame or none (counted as unpaired). Not
/// thread-safe: a source calls it under its own lock.
template <typename Depth, typename Colour>
class FramePairer {
 public:
  using Deliver = std::function<void(const Depth& depth, const Colour* colour)>;
  static constexpr std::size_t kMaxWaiting = 3;
  static constexpr std::size_t kColoursKept = 4;

  FramePairer(std::int64_t tolerance, Deliver deliver)
      : tolerance_(tolerance), deliver_(std::move(deliver)) {}

  void set_tolerance(std::int64_t tolerance) { tolerance_ = tolerance; }
  std::uint64_t unpaired() const { return unpaired_; }
  bool waiting() const { return !waiting_.empty(); }

  void AddDepth(Depth depth, std::int64_t time) {
    waiting_.push_back({std::move(depth), time});
    if (waiting_.size() > kMaxWaiting) DeliverFirst(nullptr);
    Drain();
  }

  void AddColour(Colour colour, std::int64_t time) {
    colours_.push_back({std::move(colour), time});
    if (colours_.size() > kColoursKept) colours_.pop_front();
    Drain();
  }

  /// Delivers the depth frames still waiting, without colour (the stream ended or stops).
  void Flush() {
    while (!waiting_.empty()) DeliverFirst(nullptr);
  }

  /// Forgets every frame held, delivering none (the streams are going away).
  void Clear() {
    waiting_.clear();
    colours_.clear();
  }

 private:
  template <typename T>
  struct Timed {
    T frame;
    std::int64_t time;
  };

  static std::int64_t Gap(std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; }

  // Delivers the oldest waiting depth frames that have their colour, or never will.
  void Drain() {
    while (!waiting_.empty()) {
      const std::int64_t t = waiting_.front().time;
      const Timed<Colour>* best = nullptr;
      for (const auto& c : colours_)
        if (Gap(c.time, t) <= tolerance_ && (!best || Gap(c.time, t) < Gap(best->time, t)))
          best = &c;
      if (best) {
        DeliverFirst(&best->frame);
      } else if (!colours_.empty() && colours_.back().time > t + tolerance_) {
        DeliverFirst(nullptr);  // the colour stream is past its time
      } else {
        return;
      }
    }
  }

  void DeliverFirst(const Colour* colour) {
    Timed<Depth> first = std::move(waiting_.front());
    waiting_.pop_front();
    if (!colour) ++unpaired_;
    deliver_(first.frame, colour);
  }

  std::int64_t tolerance_;
  Deliver deliver_;
  std::deque<Timed<Depth>> waiting_;
  std::deque<Timed<Colour>> colours_;
  std::uint64_t unpaired_ = 0;
};

}  // namespace saccade
