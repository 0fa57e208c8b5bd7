#include "io/sources/camera_source.h"

#include "core/fail.h"

#include <algorithm>
#include <cmath>

namespace saccade {

FrameSource::Status CameraSource::Next(Frame* frame, std::string* error) {
  auto item = mailbox_.Take();
  if (!item) return Status::kEnd;
  if (!item->ok) {
    Fail(error, item->error);
    return Status::kError;
  }
  *frame = std::move(item->frame);
  return Status::kFrame;
}

void CameraSource::Stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);  // not between a waiter's check and wait
    stopped_ = true;
  }
  mailbox_.CloseAndClear();
  wake_.notify_all();
}

SourceStats CameraSource::BaseStats() const {
  SourceStats s;
  s.produced = produced_;
  s.dropped = mailbox_.dropped();
  s.reconnects = reconnects_;
  std::lock_guard<std::mutex> lock(state_mutex_);
  s.state = state_;
  return s;
}

void CameraSource::SetState(const std::string& state) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  state_ = state;
}

void CameraSource::PostError(const std::string& error) {
  Item item;
  item.ok = false;
  item.error = error;
  mailbox_.Put(std::move(item));
  mailbox_.Close();
}

bool CameraSource::StartWaiting(const std::string& why, double wait_at_start_s) {
  if (!(wait_at_start_s > 0)) return false;
  SetState("waiting for device: " + why);
  waiting_until_ = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                       std::chrono::duration<double>(wait_at_start_s));
  return true;
}

bool CameraSource::BackOff(bool waiting, const std::string& why, std::chrono::milliseconds* backoff,
                           std::unique_lock<std::mutex>* lock) {
  const auto now = std::chrono::steady_clock::now();
  if (waiting && now >= waiting_until_) {  // the wait at start is over
    const double waited = std::chrono::duration<double>(now - started_).count();
    PostError(why + " (waited " + std::to_string(std::lround(waited)) + " s for it)");
    return false;
  }
  SetState((waiting ? "waiting for device: " : "reconnecting: ") + why);
  wake_.wait_for(*lock, *backoff, [this] { return stopped_.load(); });
  *backoff = std::min(*backoff * 2, std::chrono::milliseconds(8000));
  return true;
}

}  // namespace saccade
