// An OpenNI2 driver that serves a folder of depth images as a live depth camera, so that the
// real libOpenNI2 (device enumeration, streams, frame callbacks, openni::Recorder) runs in
// tests and demos with no sensor attached.
//
// libOpenNI2 loads every lib*.so.0 in the OpenNI2/Drivers folder beside itself. The build puts
// this driver there, next to links to Debian's libOpenNI2 and its .oni file driver (see
// io/CMakeLists.txt); LD_LIBRARY_PATH=<that folder> selects it.
//
// The device appears when SACCADE_VIRTUAL_DEVICE names a folder of 16-bit depth images
// (*depth*.png or .tiff, millimetres) with an intrinsics.yaml, as `saccade record --format
// depth` writes. Frames play in name order, looping, at SACCADE_VIRTUAL_DEVICE_FPS (default
// 30). Frame n (from 1) shows image (n - 1) mod count and has timestamp n * 1e6 / fps us.
// SACCADE_VIRTUAL_DEVICE_STALL_AFTER=N makes each opened stream fall silent after N frames,
// as an unplugged camera does, so that reconnection can be tested.
#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "io/images.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace {

constexpr char kUriPrefix[] = "saccade-virtual://";

struct Recording {
  std::vector<saccade::DepthImage> frames;
  saccade::IntrinsicsFile intrinsics;
  int fps = 30;
  int stall_after = 0;  // > 0: the stream goes silent after this many frames (an unplug)
};

bool LoadRecording(const std::string& dir, Recording* out) {
  std::string error;
  if (!saccade::ReadIntrinsicsFile(dir + "/intrinsics.yaml", &out->intrinsics, &error))
    return false;
  for (const auto& path : saccade::ListDepthImages(dir)) {
    saccade::DepthImage image;
    if (!saccade::ReadDepthImage(path, &image, &error)) return false;
    if (image.width != out->intrinsics.width || image.height != out->intrinsics.height)
      return false;
    out->frames.push_back(std::move(image));
  }
  if (const char* fps = std::getenv("SACCADE_VIRTUAL_DEVICE_FPS")) out->fps = std::atoi(fps);
  if (const char* stall = std::getenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER"))
    out->stall_after = std::atoi(stall);
  return !out->frames.empty() && out->fps > 0;
}

OniVideoMode ModeOf(const Recording& r) {
  OniVideoMode mode;
  mode.pixelFormat = ONI_PIXEL_FORMAT_DEPTH_1_MM;
  mode.resolutionX = r.intrinsics.width;
  mode.resolutionY = r.intrinsics.height;
  mode.fps = r.fps;
  return mode;
}

class DepthStream : public oni::driver::StreamBase {
 public:
  explicit DepthStream(const Recording* recording) : recording_(recording) {}
  ~DepthStream() override { stop(); }

  OniStatus start() override {
    if (running_) return ONI_STATUS_OK;
    running_ = true;
    thread_ = std::thread([this] { Run(); });
    return ONI_STATUS_OK;
  }
  void stop() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MAX_VALUE ||
           id == ONI_STREAM_PROPERTY_MIN_VALUE || id == ONI_STREAM_PROPERTY_STRIDE ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_CROPPING;
  }

  OniStatus getProperty(int id, void* data, int* size) override {
    const auto& k = recording_->intrinsics;
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE:
        return Put(ModeOf(*recording_), data, size);
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:  // fx = (width / 2) / tan(hfov / 2)
        return Put(static_cast<float>(2 * std::atan(k.width / (2 * k.fx))), data, size);
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        return Put(static_cast<float>(2 * std::atan(k.height / (2 * k.fy))), data, size);
      case ONI_STREAM_PROPERTY_MAX_VALUE:
        return Put(10000, data, size);
      case ONI_STREAM_PROPERTY_MIN_VALUE:
        return Put(0, data, size);
      case ONI_STREAM_PROPERTY_STRIDE:
        return Put(static_cast<int>(k.width * sizeof(OniDepthPixel)), data, size);
      case ONI_STREAM_PROPERTY_MIRRORING:
        return Put(OniBool(FALSE), data, size);
      case ONI_STREAM_PROPERTY_CROPPING:  // the .oni player drops frames without it
        return Put(OniCropping{FALSE, 0, 0, k.width, k.height}, data, size);
      default:
        return ONI_STATUS_NOT_SUPPORTED;
    }
  }

  // openni::Recorder stores the stream's properties from these notifications; without them
  // the .oni player cannot set the stream up and never delivers a frame.
  void notifyAllProperties() override {
    for (int id : {ONI_STREAM_PROPERTY_VIDEO_MODE, ONI_STREAM_PROPERTY_HORIZONTAL_FOV,
                   ONI_STREAM_PROPERTY_VERTICAL_FOV, ONI_STREAM_PROPERTY_MAX_VALUE,
                   ONI_STREAM_PROPERTY_MIN_VALUE, ONI_STREAM_PROPERTY_STRIDE,
                   ONI_STREAM_PROPERTY_MIRRORING, ONI_STREAM_PROPERTY_CROPPING}) {
      alignas(8) unsigned char value[64];
      int size = sizeof(value);
      if (getProperty(id, value, &size) == ONI_STATUS_OK) raisePropertyChanged(id, value, size);
    }
  }

  OniStatus setProperty(int id, const void* data, int size) override {
    if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof(OniVideoMode)) {
      const OniVideoMode& want = *static_cast<const OniVideoMode*>(data);
      const OniVideoMode have = ModeOf(*recording_);
      return want.resolutionX == have.resolutionX && want.resolutionY == have.resolutionY &&
                     want.pixelFormat == have.pixelFormat
                 ? ONI_STATUS_OK
                 : ONI_STATUS_NOT_SUPPORTED;
    }
    if (id == ONI_STREAM_PROPERTY_MIRRORING) return ONI_STATUS_OK;
    return ONI_STATUS_NOT_SUPPORTED;
  }

 private:
  // Writes a property value; `*size` is the room at `data` in, the value's size out.
  template <typename T>
  static OniStatus Put(const T& value, void* data, int* size) {
    if (*size < static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(data, &value, sizeof(T));
    *size = sizeof(T);
    return ONI_STATUS_OK;
  }

  void Run() {
    using Clock = std::chrono::steady_clock;
    const auto period = std::chrono::microseconds(1000000 / recording_->fps);
    auto due = Clock::now();
    for (int index = 1; running_; ++index) {
      due += period;
      std::this_thread::sleep_until(due);  // the camera's own frame clock
      if (recording_->stall_after > 0 && index > recording_->stall_after) continue;
      const auto& image = recording_->frames[(index - 1) % recording_->frames.size()];
      OniFrame* frame = getServices().acquireFrame();
      if (!frame) continue;
      const int bytes = static_cast<int>(image.data.size() * sizeof(OniDepthPixel));
      std::memcpy(frame->data, image.data.data(), bytes);
      frame->dataSize = bytes;
      frame->sensorType = ONI_SENSOR_DEPTH;
      frame->frameIndex = index;
      frame->timestamp = static_cast<uint64_t>(index) * 1000000u / recording_->fps;
      frame->videoMode = ModeOf(*recording_);
      frame->width = image.width;
      frame->height = image.height;
      frame->croppingEnabled = FALSE;
      frame->cropOriginX = frame->cropOriginY = 0;
      frame->stride = image.width * static_cast<int>(sizeof(OniDepthPixel));
      raiseNewFrame(frame);
      getServices().releaseFrame(frame);
    }
  }

  const Recording* recording_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

class VirtualDevice : public oni::driver::DeviceBase {
 public:
  explicit VirtualDevice(Recording recording) : recording_(std::move(recording)) {
    mode_ = ModeOf(recording_);
    sensor_.sensorType = ONI_SENSOR_DEPTH;
    sensor_.numSupportedVideoModes = 1;
    sensor_.pSupportedVideoModes = &mode_;
  }
  OniStatus getSensorInfoList(OniSensorInfo** sensors, int* count) override {
    *sensors = &sensor_;
    *count = 1;
    return ONI_STATUS_OK;
  }
  oni::driver::StreamBase* createStream(OniSensorType type) override {
    return type == ONI_SENSOR_DEPTH ? new DepthStream(&recording_) : nullptr;
  }
  void destroyStream(oni::driver::StreamBase* stream) override { delete stream; }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id != ONI_DEVICE_PROPERTY_SERIAL_NUMBER) return ONI_STATUS_NOT_SUPPORTED;
    const char serial[] = "SACCADE-VIRTUAL-0";
    if (*size < static_cast<int>(sizeof(serial))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(data, serial, sizeof(serial));
    *size = sizeof(serial);
    return ONI_STATUS_OK;
  }
  OniBool isPropertySupported(int id) override { return id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER; }

 private:
  Recording recording_;
  OniVideoMode mode_;
  OniSensorInfo sensor_;
};

class VirtualDriver : public oni::driver::DriverBase {
 public:
  explicit VirtualDriver(OniDriverServices* services) : DriverBase(services) {}

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected,
                       oni::driver::DeviceDisconnectedCallback disconnected,
                       oni::driver::DeviceStateChangedCallback changed, void* cookie) override {
    DriverBase::initialize(connected, disconnected, changed, cookie);
    const char* dir = std::getenv("SACCADE_VIRTUAL_DEVICE");
    if (!dir || !*dir) return ONI_STATUS_OK;  // no folder, no device
    dir_ = dir;
    OniDeviceInfo info{};
    std::snprintf(info.uri, sizeof(info.uri), "%s%s", kUriPrefix, dir);
    std::snprintf(info.vendor, sizeof(info.vendor), "Saccade");
    std::snprintf(info.name, sizeof(info.name), "Virtual depth camera");
    deviceConnected(&info);
    return ONI_STATUS_OK;
  }

  oni::driver::DeviceBase* deviceOpen(const char* uri, const char* /*mode*/) override {
    if (std::strncmp(uri, kUriPrefix, std::strlen(kUriPrefix)) != 0) return nullptr;
    Recording recording;
    if (!LoadRecording(uri + std::strlen(kUriPrefix), &recording)) return nullptr;
    return new VirtualDevice(std::move(recording));
  }
  void deviceClose(oni::driver::DeviceBase* device) override { delete device; }
  void shutdown() override {}
  OniStatus tryDevice(const char* uri) override {
    return std::strncmp(uri, kUriPrefix, std::strlen(kUriPrefix)) == 0 ? ONI_STATUS_OK
                                                                       : ONI_STATUS_ERROR;
  }

 private:
  std::string dir_;
};

}  // namespace

ONI_EXPORT_DRIVER(VirtualDriver)
