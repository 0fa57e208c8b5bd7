#include "io/openni2_source.h"

#include "core/fail.h"

#include "io/mailbox.h"

#include <OpenNI.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace saccade {

namespace {

using Clock = std::chrono::steady_clock;

std::string LastOpenNIError() {
  const char* e = openni::OpenNI::getExtendedError();
  std::string s = e && *e ? e : "no detail from libOpenNI2";
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

// libOpenNI2 is initialized once per process and stays up: its drivers own threads that
// outlive any one source.
bool InitializeOpenNI(std::string* error) {
  static std::mutex mutex;
  static bool initialized = false;
  std::lock_guard<std::mutex> lock(mutex);
  if (initialized) return true;
  if (openni::OpenNI::initialize() != openni::STATUS_OK)
    return Fail(error, "libOpenNI2: initialization failed: " + LastOpenNIError());
  initialized = true;
  return true;
}

// A pinhole model from the stream's fields of view, with the centre at the middle of the
// image as PCL's OpenNI2 grabber assumes.
CameraIntrinsics IntrinsicsOf(openni::VideoStream& stream) {
  const openni::VideoMode mode = stream.getVideoMode();
  CameraIntrinsics k;
  k.width = mode.getResolutionX();
  k.height = mode.getResolutionY();
  k.fx = k.width / (2.0 * std::tan(stream.getHorizontalFieldOfView() / 2.0));
  k.fy = k.height / (2.0 * std::tan(stream.getVerticalFieldOfView() / 2.0));
  k.cx = (k.width - 1) / 2.0;
  k.cy = (k.height - 1) / 2.0;
  return k;
}

bool ToFrame(const openni::VideoFrameRef& ref, const CameraIntrinsics& k, Frame* frame,
             std::string* error) {
  const auto format = ref.getVideoMode().getPixelFormat();
  if (format != openni::PIXEL_FORMAT_DEPTH_1_MM && format != openni::PIXEL_FORMAT_DEPTH_100_UM)
    return Fail(error, "OpenNI2 stream: not a depth format (" + std::to_string(format) + ")");
  if (ref.getWidth() != k.width || ref.getHeight() != k.height || ref.getCropOriginX() != 0)
    return Fail(error, "OpenNI2 stream: frame size differs from the stream's video mode");
  const auto* data = static_cast<const std::uint16_t*>(ref.getData());
  // Millimetres packed row after row are the common case and convert in place; other layouts
  // are repacked first.
  std::vector<std::uint16_t> mm;
  const bool packed = ref.getStrideInBytes() == k.width * static_cast<int>(sizeof(std::uint16_t));
  if (!packed || format == openni::PIXEL_FORMAT_DEPTH_100_UM) {
    mm.resize(static_cast<std::size_t>(k.width) * k.height);
    const auto* bytes = static_cast<const std::uint8_t*>(ref.getData());
    for (int v = 0; v < k.height; ++v) {
      const auto* row = reinterpret_cast<const std::uint16_t*>(bytes + v * ref.getStrideInBytes());
      for (int u = 0; u < k.width; ++u)
        mm[static_cast<std::size_t>(v) * k.width + u] =
            format == openni::PIXEL_FORMAT_DEPTH_100_UM ? row[u] / 10 : row[u];
    }
    data = mm.data();
  }
  frame->intrinsics = k;
  frame->cloud = std::make_shared<const Cloud>(DepthToCloud(data, nullptr, k));
  frame->capture_utime = static_cast<std::int64_t>(ref.getTimestamp());
  return true;
}

// The URI of `device` ("" the first, "#N" the N-th, a URI or a serial number) among the
// devices libOpenNI2 lists now; false with one line naming the spec when there is none.
bool ResolveDevice(const std::string& device, std::string* uri, std::string* error) {
  const std::string spec = "openni2://" + device;
  uri->clear();
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

// What the device and playback sources share: one depth stream, a recorder, the mailbox that
// OpenNI2's callback thread fills, and the counters.
class StreamSource : public OpenNI2Source, public openni::VideoStream::NewFrameListener {
 public:
  // Each derived class stops and closes the stream in its own destructor, while onNewFrame
  // still resolves to it; by the time this one runs the stream is closed.
  ~StreamSource() override = default;

  Status Next(Frame* frame, std::string* error) override {
    auto item = mailbox_.Take();
    if (!item) return Status::kEnd;
    if (!item->ok) {
      Fail(error, item->error);
      return Status::kError;
    }
    *frame = std::move(item->frame);
    return Status::kFrame;
  }

  void Stop() override {
    stopped_ = true;
    mailbox_.CloseAndClear();
    wake_.notify_all();
  }

  SourceStats Stats() const override {
    SourceStats s;
    s.produced = produced_;
    s.dropped = mailbox_.dropped() + skipped_;
    s.reconnects = reconnects_;
    std::lock_guard<std::mutex> lock(mutex_);
    s.state = state_;
    return s;
  }

  bool StartRecording(const std::string& path, std::string* error) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (recorder_.isValid()) return Fail(error, path + ": already recording");
    if (recorder_.create(path.c_str()) != openni::STATUS_OK ||
        recorder_.attach(depth_) != openni::STATUS_OK || recorder_.start() != openni::STATUS_OK) {
      recorder_.destroy();
      return Fail(error, path + ": cannot record: " + LastOpenNIError());
    }
    return true;
  }

  void StopRecording() override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!recorder_.isValid()) return;
    recorder_.stop();
    recorder_.destroy();
  }

 protected:
  struct Item {
    bool ok = true;
    Frame frame;
    std::string error;
  };

  // Opens `uri` and its depth stream; the listener starts delivering frames.
  bool OpenStream(const std::string& uri, std::string* error) {
    if (device_.open(uri.c_str()) != openni::STATUS_OK)
      return Fail(error, uri + ": cannot open: " + LastOpenNIError());
    if (!device_.hasSensor(openni::SENSOR_DEPTH) ||
        depth_.create(device_, openni::SENSOR_DEPTH) != openni::STATUS_OK) {
      device_.close();
      return Fail(error, uri + ": no depth stream: " + LastOpenNIError());
    }
    intrinsics_ = IntrinsicsOf(depth_);
    return true;
  }

  bool StartStream(std::string* error) {
    depth_.addNewFrameListener(this);
    if (depth_.start() != openni::STATUS_OK) {
      depth_.removeNewFrameListener(this);
      return Fail(error, "cannot start the depth stream: " + LastOpenNIError());
    }
    return true;
  }

  void CloseStream() {
    StopRecording();
    if (depth_.isValid()) {
      depth_.removeNewFrameListener(this);
      depth_.stop();
      depth_.destroy();
    }
    if (device_.isValid()) device_.close();
  }

  // Reads one frame of the stream into an Item with the next sequence number.
  Item ReadOne() {
    Item item;
    openni::VideoFrameRef ref;
    if (depth_.readFrame(&ref) != openni::STATUS_OK) {
      item.ok = false;
      item.error = "OpenNI2 stream: cannot read a frame: " + LastOpenNIError();
      return item;
    }
    // Frames libOpenNI2 skipped before reaching us count as dropped too.
    if (last_index_ > 0 && ref.getFrameIndex() > last_index_ + 1)
      skipped_ += static_cast<std::uint64_t>(ref.getFrameIndex() - last_index_ - 1);
    last_index_ = ref.getFrameIndex();
    item.ok = ToFrame(ref, intrinsics_, &item.frame, &item.error);
    item.frame.sequence = sequence_++;
    item.frame.arrival_steady_ns = SteadyNowNs();
    ++produced_;
    return item;
  }

  void SetState(const std::string& state) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = state;
  }

  openni::Device device_;
  openni::VideoStream depth_;
  openni::Recorder recorder_;
  CameraIntrinsics intrinsics_;
  LatestMailbox<Item> mailbox_;
  std::atomic<bool> stopped_{false};
  std::atomic<std::uint64_t> produced_{0}, reconnects_{0}, skipped_{0};
  std::uint64_t sequence_ = 0;
  int last_index_ = 0;  // OpenNI2's own frame index of the last frame read
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::string state_ = "streaming";
};

class DeviceSource : public StreamSource {
 public:
  // Opens `device` (a spec's target); when it is not there and wait_at_start_s > 0, waits for
  // it in the background (state "waiting for device: why") with the back-off of a reconnect,
  // and past the wait posts the error Next() returns.
  bool Open(const std::string& device, double wait_at_start_s, std::string* error) {
    device_spec_ = device;
    std::string why;
    const bool opened = Connect(&why);
    if (!opened && !(wait_at_start_s > 0)) return Fail(error, why);
    if (!opened) {
      SetState("waiting for device: " + why);
      waiting_until_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(wait_at_start_s));
    }
    last_frame_ = Clock::now().time_since_epoch().count();
    watchdog_ = std::thread([this, opened] { Watch(!opened); });
    return true;
  }
  ~DeviceSource() override {
    Stop();
    if (watchdog_.joinable()) watchdog_.join();
    CloseStream();  // here, while onNewFrame still resolves to this class
  }

  void onNewFrame(openni::VideoStream&) override {
    last_frame_ = Clock::now().time_since_epoch().count();
    mailbox_.Put(ReadOne());
  }
  bool Live() const override { return true; }
  std::string Describe() const override {
    return "openni2://" + (uri_.empty() ? device_spec_ : uri_);
  }

 private:
  // Finds the device and starts its depth stream; false with why not (closed again).
  bool Connect(std::string* why) {
    std::string uri;
    if (ResolveDevice(device_spec_, &uri, why) && OpenStream(uri, why) && StartStream(why)) {
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
    std::unique_lock<std::mutex> lock(watch_mutex_);
    while (!stopped_) {
      if (!waiting) {
        wake_.wait_for(lock, std::chrono::milliseconds(250));
        if (stopped_) break;
        const Clock::time_point last{Clock::duration(last_frame_.load())};
        if (Clock::now() - last < stall) continue;
        SetState("reconnecting: no frame for 2 s");
        CloseStream();
      }
      auto backoff = std::chrono::milliseconds(500);
      while (!stopped_) {
        std::string why;
        if (Connect(&why)) {
          if (!waiting) ++reconnects_;
          last_frame_ = Clock::now().time_since_epoch().count();
          SetState("streaming");
          break;
        }
        if (waiting && Clock::now() >= waiting_until_) {  // the wait at start is over
          Item item;
          item.ok = false;
          item.error = why + " (waited " +
                       std::to_string(static_cast<long long>(std::lround(
                           std::chrono::duration<double>(Clock::now() - started_).count()))) +
                       " s for it)";
          mailbox_.Put(std::move(item));
          return;
        }
        SetState((waiting ? "waiting for device: " : "reconnecting: ") + why);
        wake_.wait_for(lock, backoff);
        backoff = std::min(backoff * 2, std::chrono::milliseconds(8000));
      }
      waiting = false;
    }
  }

  std::string device_spec_;  // "", "#N", a URI or a serial number
  std::string uri_;          // the device's URI once found
  const Clock::time_point started_ = Clock::now();
  Clock::time_point waiting_until_;
  std::atomic<Clock::rep> last_frame_{0};
  std::mutex watch_mutex_;
  std::thread watchdog_;
};

class PlaybackSource : public StreamSource {
 public:
  bool Open(const std::string& path, const OniPlaybackOptions& options, std::string* error) {
    path_ = path;
    options_ = options;
    if (!OpenStream(path, error)) return false;
    openni::PlaybackControl* control = device_.getPlaybackControl();
    if (!control) return Fail(error, path + ": not a recording");
    using Mode = OniPlaybackOptions::Mode;
    const float speed = options.mode == Mode::kRealtime ? 1.0f
                        : options.mode == Mode::kFast   ? 0.0f
                                                        : -1.0f;  // manual: one per read
    control->setSpeed(speed);
    // The end of a non-looping recording is detected here by counting frames. The player is
    // always left repeating: at the end of a file it otherwise spins over its stream list,
    // racing the destruction of the stream (Debian's libOniFile crashed so under load).
    control->setRepeatEnabled(true);
    frames_ = control->getNumberOfFrames(depth_);
    if (frames_ <= 0) return Fail(error, path + ": the recording has no depth frame");
    if (options.mode == Mode::kStep) {
      if (depth_.start() != openni::STATUS_OK)
        return Fail(error, path + ": cannot start playback: " + LastOpenNIError());
      return true;
    }
    return StartStream(error);
  }

  ~PlaybackSource() override {
    Stop();
    if (depth_.isValid()) {
      depth_.removeNewFrameListener(this);
      depth_.stop();
      // libOniFile's player thread walks its stream list every 10 ms without a lock while no
      // stream runs; give it that beat to leave the walk before the stream is destroyed.
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    CloseStream();
  }

  Status Next(Frame* frame, std::string* error) override {
    if (options_.mode != OniPlaybackOptions::Mode::kStep) return StreamSource::Next(frame, error);
    if (stopped_ || (!options_.loop && read_ >= frames_)) {
      SetState("ended");
      return Status::kEnd;
    }
    // In manual playback the file driver reads the next frame when asked through
    // waitForAnyStream (its manual trigger); a timeout keeps Stop() responsive.
    for (;;) {
      openni::VideoStream* streams[] = {&depth_};
      int ready = -1;
      const auto rc = openni::OpenNI::waitForAnyStream(streams, 1, &ready, 500);
      if (rc == openni::STATUS_OK) break;
      if (stopped_) return Status::kEnd;
      if (rc != openni::STATUS_TIME_OUT) {
        Fail(error, path_ + ": playback failed: " + LastOpenNIError());
        return Status::kError;
      }
    }
    Item item = ReadOne();
    ++read_;
    if (!item.ok) {
      Fail(error, path_ + ": " + item.error);
      return Status::kError;
    }
    *frame = std::move(item.frame);
    return Status::kFrame;
  }

  void onNewFrame(openni::VideoStream&) override {
    if (stopped_ || ended_) return;
    const int previous = last_index_;
    Item item = ReadOne();
    // The player repeats (see Open): a non-looping playback ends at the last frame, or at the
    // wrap when libOpenNI2 skipped the last frame in fast mode.
    const bool wrapped = last_index_ < previous;
    if (!(wrapped && !options_.loop)) mailbox_.Put(std::move(item));
    if (!options_.loop && (wrapped || last_index_ >= frames_)) {
      ended_ = true;
      SetState("ended");
      mailbox_.Close();
    }
  }
  bool Live() const override { return options_.mode != OniPlaybackOptions::Mode::kStep; }
  std::string Describe() const override {
    return path_ + " (" + std::to_string(frames_) + " frames)";
  }

 private:
  std::string path_;
  OniPlaybackOptions options_;
  int frames_ = 0;
  int read_ = 0;
  std::atomic<bool> ended_{false};
};

}  // namespace

std::unique_ptr<OpenNI2Source> OpenOpenNI2Device(const std::string& device, double wait_at_start_s,
                                                 std::string* error) {
  if (!InitializeOpenNI(error)) return nullptr;
  auto source = std::make_unique<DeviceSource>();
  if (!source->Open(device, wait_at_start_s, error)) return nullptr;
  return source;
}

std::unique_ptr<OpenNI2Source> OpenOniPlayback(const std::string& path,
                                               const OniPlaybackOptions& options,
                                               std::string* error) {
  if (!InitializeOpenNI(error)) return nullptr;
  if (FILE* f = std::fopen(path.c_str(), "rb")) {
    std::fclose(f);
  } else {
    Fail(error, path + ": cannot open recording");
    return nullptr;
  }
  auto source = std::make_unique<PlaybackSource>();
  if (!source->Open(path, options, error)) return nullptr;
  return source;
}

}  // namespace saccade
