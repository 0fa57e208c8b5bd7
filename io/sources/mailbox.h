// A single-slot latest-value mailbox: a producer that must never block (a sensor) overwrites
// what the consumer has not taken yet, and the overwritten values are counted.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

namespace saccade {

/// Thread-safe for one or more producers and consumers.
template <typename T>
class LatestMailbox {
 public:
  /// Stores `value`, replacing (and counting as dropped) one not yet taken. Never blocks for
  /// longer than the lock. Once closed, the value is dropped (and counted).
  void Put(T value) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) {
        ++dropped_;
        return;
      }
      if (slot_) ++dropped_;
      slot_ = std::move(value);
    }
    ready_.notify_one();
  }

  /// Blocks until a value is there (returns it) or the mailbox is closed and empty (nullopt).
  std::optional<T> Take() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [this] { return slot_.has_value() || closed_; });
    std::optional<T> out = std::move(slot_);
    slot_.reset();
    lock.unlock();
    taken_.notify_all();
    return out;
  }

  /// Blocks until the stored value has been taken or the mailbox is closed: for a producer
  /// that must not lose values (a replay), before its next Put.
  void WaitUntilTaken() {
    std::unique_lock<std::mutex> lock(mutex_);
    taken_.wait(lock, [this] { return !slot_.has_value() || closed_; });
  }

  /// No more values: wakes every waiting Take(). A value already stored can still be taken.
  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
    taken_.notify_all();
  }

  /// Drops (and counts) the stored value too: an immediate stop.
  void CloseAndClear() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      if (slot_) ++dropped_;
      slot_.reset();
    }
    ready_.notify_all();
    taken_.notify_all();
  }

  std::uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_, taken_;
  std::optional<T> slot_;
  bool closed_ = false;
  std::uint64_t dropped_ = 0;
};

}  // namespace saccade
