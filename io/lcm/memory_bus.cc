#include "io/lcm/memory_bus.h"

namespace saccade {

bool MemoryBus::Publish(const FrameDetections& frame, const Fixation& fixation) {
  std::lock_guard<std::mutex> lock(mutex_);
  frames_.push_back({frame, fixation});
  return true;
}

bool MemoryBus::PublishStatus(const StatusReport& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  statuses_.push_back(status);
  return true;
}

bool MemoryBus::PublishPreview(const Preview& preview, std::int64_t, const PreviewOptions&,
                               std::string*) {
  std::lock_guard<std::mutex> lock(mutex_);
  previews_.push_back(preview);
  return true;
}

void MemoryBus::Subscribe(CommandHandler handler) {
  std::lock_guard<std::mutex> lock(mutex_);
  handler_ = std::move(handler);
}

std::int64_t MemoryBus::AcceptedCommands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return accepted_;
}

std::int64_t MemoryBus::RejectedCommands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rejected_;
}

bool MemoryBus::Send(const Command& command) {
  CommandHandler handler;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    handler = handler_;
  }
  if (!handler) return false;
  handler(command, [this](bool accepted, const std::string& /*why*/) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++(accepted ? accepted_ : rejected_);
  });
  return true;
}

std::vector<MemoryBus::Published> MemoryBus::Frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_;
}

std::vector<Preview> MemoryBus::Previews() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return previews_;
}

std::vector<StatusReport> MemoryBus::Statuses() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return statuses_;
}

}  // namespace saccade
