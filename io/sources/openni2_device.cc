// Live OpenNI2 devices: found by index, URI or serial number, reopened with back-off when
// their frames stop.
#include "core/fail.h"
#include "io/base/log.h"
#include "io/sources/openni2_stream.h"

#include <algorithm>
#include <cstdlib>
#include <thread>

namespace saccade {

namespace openni2_internal {
namespace {

// The URI of `device` ("" the first, "#N" the N-th, a URI or a serial number) among the
// devices libOpenNI2 lists now; false with one line naming the spec when there is none.
bool ResolveDevice(const std::string& device, std::string* uri, std::string* error) {
  const std::string spec = "openni2://" + device;
  uri->clear();
  // A URI is opened as it is: libOpenNI2 asks its drivers about one it has not listed (a file,
  // a folder of the virtual device), and says why when none takes it.
  if (device.find("://") != std::string::npos) {
    *uri = device;
    return true;
  }
  openni::Array<openni::DeviceInfo> list;
  openni::OpenNI::enumerateDevices(&list);
  std::vector<std::string> uris;
  for (int i = 0; i < list.getSize(); ++i) uris.push_back(list[i].getUri());
  if (uris.empty()) {
    Fail(error, spec +
                    ": no OpenNI2 device found (libOpenNI2 and its drivers list none; is a "
                    "sensor plugged in and readable by this user?)");
    return false;
  }
  if (device.empty()) {
    *uri = uris.front();
  } else if (device[0] == '#') {
    char* end = nullptr;
    const long n = std::strtol(device.c_str() + 1, &end, 10);
    if (device.size() < 2 || *end != '\0' || n < 0 || n >= static_cast<long>(uris.size())) {
      Fail(error, spec + ": no such device; " + std::to_string(uris.size()) +
                      " found (openni2://#0 is the first)");
      return false;
    }
    *uri = uris[static_cast<std::size_t>(n)];
  } else {
    for (const auto& u : uris)
      if (u == device) *uri = u;
    for (std::size_t i = 0; uri->empty() && i < uris.size(); ++i) {  // a serial number
      openni::Device d;
      if (d.open(uris[i].c_str()) != openni::STATUS_OK) continue;
      char serial[128] = {};
      int size = sizeof(serial);
      if (d.getProperty(ONI_DEVICE_PROPERTY_SERIAL_NUMBER, serial, &size) == openni::STATUS_OK &&
          device == serial)
        *uri = uris[i];
      d.close();
    }
    if (uri->empty()) {
      std::string all;
      for (const auto& u : uris) all += (all.empty() ? "" : ", ") + u;
      Fail(error, spec + ": no device with that URI or serial number (found: " + all + ")");
      return false;
    }
  }
  return true;
}

class DeviceSource : public StreamSource {
 public:
  using StreamSource::StreamSource;
  // Opens `device` (a spec's target); when it is not there and wait_at_start_s > 0, waits for
  // it in the background (state "waiting for device: why") with the back-off of a reconnect,
  // and past the wait posts the error Next() returns.
  bool Open(const std::string& device, double wait_at_start_s, std::string* error) {
    device_spec_ = device;
    std::string why;
    const bool opened = Connect(&why);
    if (!opened && !StartWaiting(why, wait_at_start_s)) return Fail(error, why);
    last_frame_ = Clock::now().time_since_epoch().count();
    watchdog_ = std::thread([this, opened] { Watch(!opened); });
    return true;
  }
  ~DeviceSource() override {
    Stop();
    if (watchdog_.joinable()) watchdog_.join();
    CloseStream();  // here, while OnFrame still resolves to this class
  }

  void OnFrame(bool depth) override {
    if (depth) last_frame_ = Clock::now().time_since_epoch().count();
    ReadAndPair(depth, [this](Item item) { mailbox_.Put(std::move(item)); });
  }
  bool Live() const override { return true; }
  std::string Describe() const override {
    return "openni2://" + (uri_.empty() ? device_spec_ : uri_);
  }

 private:
  // Finds the device and starts its streams; false with why not (closed again).
  bool Connect(std::string* why) {
    std::string uri;
    if (ResolveDevice(device_spec_, &uri, why) && OpenStream(uri, true, why) && StartStream(why)) {
      uri_ = uri;
      return true;
    }
    CloseStream();
    return false;
  }

  // Reopens the device when frames stop (unplugged, powered down, a stalled driver), and at
  // start waits for one that is not there yet: back-off 0.5 s doubling to 8 s.
  void Watch(bool waiting) {
    const auto stall = std::chrono::seconds(2);
    std::unique_lock<std::mutex> lock(wake_mutex_);
    while (!stopped_) {
      if (!waiting) {
        wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stopped_.load(); });
        if (stopped_) break;
        const Clock::time_point last{Clock::duration(last_frame_.load())};
        if (Clock::now() - last < stall) continue;
        SetState("reconnecting: no frame for 2 s");
        lock.unlock();  // Stop() takes the lock only to say so; it must not wait for this
        CloseStream();
        lock.lock();
      }
      auto backoff = std::chrono::milliseconds(500);
      while (!stopped_) {
        std::string why;
        lock.unlock();
        const bool connected = Connect(&why);
        lock.lock();
        if (connected) {
          if (!waiting) ++reconnects_;
          last_frame_ = Clock::now().time_since_epoch().count();
          SetState("streaming");
          break;
        }
        if (!BackOff(waiting, why, &backoff, &lock)) return;
      }
      waiting = false;
    }
  }

  std::string device_spec_;  // "", "#N", a URI or a serial number
  std::string uri_;          // the device's URI once found
  std::atomic<Clock::rep> last_frame_{0};
  std::thread watchdog_;
};

}  // namespace
}  // namespace openni2_internal

std::unique_ptr<OpenNI2Source> OpenOpenNI2Device(const std::string& device,
                                                 const ColourOptions& colour,
                                                 double wait_at_start_s, std::string* error) {
  if (!openni2_internal::InitializeOpenNI(error)) return nullptr;
  auto source = std::make_unique<openni2_internal::DeviceSource>(colour);
  if (!source->Open(device, wait_at_start_s, error)) return nullptr;
  return source;
}

}  // namespace saccade
