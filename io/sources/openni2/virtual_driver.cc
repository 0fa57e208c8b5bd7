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
// 30). Frame n (from 1) shows image (n - 1) mod count and has timestamp n * 1e6 / fps us, on
// every stream: the streams share the device's frame clock.
//
// Colour: when every depth image has its rgb partner (RgbPartner), the device also has a
// colour sensor (RGB888). With a colour.yaml (io/formats/images.h) the colour images are the view
// of a second camera placed as that file says, and the device offers depth-to-colour registration
// as a PS1080 does: the depth stream then serves the depth seen from the colour camera, with
// its intrinsics. Without colour.yaml the colour images are already registered to the depth.
// SACCADE_VIRTUAL_DEVICE_REGISTRATION=0 withholds registration (as a device that has none).
//
// SACCADE_VIRTUAL_DEVICE_STALL_AFTER=N makes each opened stream fall silent after N frames,
// as an unplugged camera does, so that reconnection can be tested.
#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "core/registration.h"
#include "io/formats/images.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace {

constexpr char kUriPrefix[] = "saccade-virtual://";

struct Recording {
  std::vector<saccade::DepthImage> frames;  // the depth camera's view
  std::vector<saccade::RgbImage> colour;    // the colour camera's view, one a frame, or none
  // The depth seen from the colour camera, one a frame, when registration can be offered.
  std::vector<std::vector<std::uint16_t>> registered;
  saccade::IntrinsicsFile intrinsics;         // the depth camera
  saccade::IntrinsicsFile colour_intrinsics;  // the colour camera
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
    const std::string rgb_path = saccade::RgbPartner(path);
    if (rgb_path.empty()) continue;
    saccade::RgbImage rgb;
    if (!saccade::ReadRgbImage(rgb_path, &rgb, &error)) return false;
    if (!out->colour.empty() &&
        (rgb.width != out->colour[0].width || rgb.height != out->colour[0].height))
      return false;  // one colour stream, one size
    out->colour.push_back(std::move(rgb));
  }
  if (!out->colour.empty() && out->colour.size() != out->frames.size()) return false;
  if (const char* fps = std::getenv("SACCADE_VIRTUAL_DEVICE_FPS")) out->fps = std::atoi(fps);
  if (const char* stall = std::getenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER"))
    out->stall_after = std::atoi(stall);
  if (out->frames.empty() || out->fps <= 0) return false;
  if (out->colour.empty()) return true;
  saccade::ColourCameraFile camera;
  camera.intrinsics = out->intrinsics;
  const std::string camera_path = dir + "/" + saccade::kColourCameraFileName;
  const bool second_camera = std::ifstream(camera_path).good();
  if (second_camera && !saccade::ReadColourCameraFile(camera_path, &camera, &error)) return false;
  out->colour_intrinsics = camera.intrinsics;
  if (out->colour[0].width != camera.intrinsics.width ||
      out->colour[0].height != camera.intrinsics.height) {
    if (second_camera) return false;                      // the file describes other images
    out->colour_intrinsics.width = out->colour[0].width;  // colour of another size, unregistered
    out->colour_intrinsics.height = out->colour[0].height;
  }
  const char* registration = std::getenv("SACCADE_VIRTUAL_DEVICE_REGISTRATION");
  const bool same_size = out->colour_intrinsics.width == out->intrinsics.width &&
                         out->colour_intrinsics.height == out->intrinsics.height;
  if (!same_size || (registration && std::string(registration) == "0")) return true;
  const Eigen::Isometry3d colour_from_depth = saccade::ColourFromDepth(camera.t, camera.r);
  for (const auto& depth : out->frames)
    out->registered.push_back(
        second_camera ? saccade::RegisterDepth(depth.data.data(), out->intrinsics.Camera(),
                                               colour_from_depth, camera.intrinsics.Camera())
                      : depth.data);
  return true;
}

class ImageStream;

// What the streams share: the recording, whether the depth is registered to colour now, and
// the device's frame clock: one thread raises frame n of every started stream, colour first,
// as a sensor that synchronises its streams does.
class DeviceState {
 public:
  explicit DeviceState(Recording r) : recording(std::move(r)) {}
  ~DeviceState();
  void Start(ImageStream* stream);
  void Stop(ImageStream* stream);

  const Recording recording;
  std::atomic<bool> registered{false};

 private:
  void Run();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<ImageStream*> streams_;  // started, colour before depth
  bool quit_ = false;
  std::thread thread_;
};

class ImageStream : public oni::driver::StreamBase {
 public:
  ImageStream(DeviceState* device, OniSensorType type) : device_(device), type_(type) {}
  ~ImageStream() override { stop(); }

  OniStatus start() override {
    sent_ = 0;
    device_->Start(this);
    return ONI_STATUS_OK;
  }
  void stop() override { device_->Stop(this); }
  OniSensorType type() const { return type_; }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MAX_VALUE ||
           id == ONI_STREAM_PROPERTY_MIN_VALUE || id == ONI_STREAM_PROPERTY_STRIDE ||
           id == ONI_STREAM_PROPERTY_MIRRORING || id == ONI_STREAM_PROPERTY_CROPPING;
  }

  OniStatus getProperty(int id, void* data, int* size) override {
    const auto k = Camera();
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE:
        return Put(Mode(), data, size);
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:  // fx = (width / 2) / tan(hfov / 2)
        return Put(static_cast<float>(2 * std::atan(k.width / (2 * k.fx))), data, size);
      case ONI_STREAM_PROPERTY_VERTICAL_FOV:
        return Put(static_cast<float>(2 * std::atan(k.height / (2 * k.fy))), data, size);
      case ONI_STREAM_PROPERTY_MAX_VALUE:
        return Put(type_ == ONI_SENSOR_DEPTH ? 10000 : 255, data, size);
      case ONI_STREAM_PROPERTY_MIN_VALUE:
        return Put(0, data, size);
      case ONI_STREAM_PROPERTY_STRIDE:
        return Put(k.width * PixelBytes(), data, size);
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
      const OniVideoMode have = Mode();
      return want.resolutionX == have.resolutionX && want.resolutionY == have.resolutionY &&
                     want.pixelFormat == have.pixelFormat
                 ? ONI_STATUS_OK
                 : ONI_STATUS_NOT_SUPPORTED;
    }
    if (id == ONI_STREAM_PROPERTY_MIRRORING) return ONI_STATUS_OK;
    return ONI_STATUS_NOT_SUPPORTED;
  }

  static OniVideoMode ModeOf(const Recording& r, OniSensorType type) {
    OniVideoMode mode;
    const bool depth = type == ONI_SENSOR_DEPTH;
    mode.pixelFormat = depth ? ONI_PIXEL_FORMAT_DEPTH_1_MM : ONI_PIXEL_FORMAT_RGB888;
    mode.resolutionX = depth ? r.intrinsics.width : r.colour_intrinsics.width;
    mode.resolutionY = depth ? r.intrinsics.height : r.colour_intrinsics.height;
    mode.fps = r.fps;
    return mode;
  }

 private:
  OniVideoMode Mode() const { return ModeOf(device_->recording, type_); }
  int PixelBytes() const {
    return type_ == ONI_SENSOR_DEPTH ? sizeof(OniDepthPixel) : sizeof(OniRGB888Pixel);
  }
  // The camera this stream's images are from: registered depth is the colour camera's view.
  const saccade::IntrinsicsFile& Camera() const {
    const Recording& r = device_->recording;
    return type_ == ONI_SENSOR_COLOR || device_->registered ? r.colour_intrinsics : r.intrinsics;
  }

  // Writes a property value; `*size` is the room at `data` in, the value's size out.
  template <typename T>
  static OniStatus Put(const T& value, void* data, int* size) {
    if (*size < static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(data, &value, sizeof(T));
    *size = sizeof(T);
    return ONI_STATUS_OK;
  }

 public:
  // Raises frame `index` of the device's clock (from 1): image (index - 1) mod count.
  void Emit(int index) {
    const Recording& r = device_->recording;
    if (r.stall_after > 0 && ++sent_ > r.stall_after) return;  // unplugged
    const std::size_t image = static_cast<std::size_t>(index - 1) % r.frames.size();
    const void* pixels = nullptr;
    if (type_ == ONI_SENSOR_COLOR) {
      pixels = r.colour[image].data.data();
    } else {
      pixels = device_->registered ? r.registered[image].data() : r.frames[image].data.data();
    }
    OniFrame* frame = getServices().acquireFrame();
    if (!frame) return;
    const auto& k = Camera();
    const int bytes = k.width * k.height * PixelBytes();
    std::memcpy(frame->data, pixels, bytes);
    frame->dataSize = bytes;
    frame->sensorType = type_;
    frame->frameIndex = index;
    frame->timestamp = static_cast<uint64_t>(index) * 1000000u / r.fps;
    frame->videoMode = Mode();
    frame->width = k.width;
    frame->height = k.height;
    frame->croppingEnabled = FALSE;
    frame->cropOriginX = frame->cropOriginY = 0;
    frame->stride = k.width * PixelBytes();
    raiseNewFrame(frame);
    getServices().releaseFrame(frame);
  }

 private:
  DeviceState* device_;
  const OniSensorType type_;
  int sent_ = 0;  // frames raised since the stream started
};

DeviceState::~DeviceState() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DeviceState::Start(ImageStream* stream) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (std::find(streams_.begin(), streams_.end(), stream) != streams_.end()) return;
  if (stream->type() == ONI_SENSOR_COLOR) {
    streams_.insert(streams_.begin(), stream);
  } else {
    streams_.push_back(stream);
  }
  if (!thread_.joinable()) thread_ = std::thread([this] { Run(); });
}

void DeviceState::Stop(ImageStream* stream) {
  std::lock_guard<std::mutex> lock(mutex_);  // not while Run raises a frame of it
  streams_.erase(std::remove(streams_.begin(), streams_.end(), stream), streams_.end());
}

// Frame n is due at start + n periods (the camera's own clock).
void DeviceState::Run() {
  const auto period = std::chrono::microseconds(1000000 / recording.fps);
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  for (int index = 1; !quit_; ++index) {
    if (wake_.wait_until(lock, start + index * period, [this] { return quit_; })) break;
    for (ImageStream* stream : streams_) stream->Emit(index);
  }
}

class VirtualDevice : public oni::driver::DeviceBase {
 public:
  explicit VirtualDevice(Recording recording) : state_(std::move(recording)) {
    const Recording& r = state_.recording;
    modes_[0] = ImageStream::ModeOf(r, ONI_SENSOR_DEPTH);
    modes_[1] = ImageStream::ModeOf(r, ONI_SENSOR_COLOR);
    sensors_[0].sensorType = ONI_SENSOR_DEPTH;
    sensors_[1].sensorType = ONI_SENSOR_COLOR;
    for (int i = 0; i < 2; ++i) {
      sensors_[i].numSupportedVideoModes = 1;
      sensors_[i].pSupportedVideoModes = &modes_[i];
    }
  }
  OniStatus getSensorInfoList(OniSensorInfo** sensors, int* count) override {
    *sensors = sensors_;
    *count = state_.recording.colour.empty() ? 1 : 2;
    return ONI_STATUS_OK;
  }
  oni::driver::StreamBase* createStream(OniSensorType type) override {
    if (type == ONI_SENSOR_COLOR && state_.recording.colour.empty()) return nullptr;
    if (type != ONI_SENSOR_DEPTH && type != ONI_SENSOR_COLOR) return nullptr;
    return new ImageStream(&state_, type);
  }
  void destroyStream(oni::driver::StreamBase* stream) override { delete stream; }
  OniStatus getProperty(int id, void* data, int* size) override {
    if (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION) {
      if (*size < static_cast<int>(sizeof(OniImageRegistrationMode)))
        return ONI_STATUS_BAD_PARAMETER;
      const OniImageRegistrationMode mode =
          state_.registered ? ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR : ONI_IMAGE_REGISTRATION_OFF;
      std::memcpy(data, &mode, sizeof(mode));
      *size = sizeof(mode);
      return ONI_STATUS_OK;
    }
    if (id != ONI_DEVICE_PROPERTY_SERIAL_NUMBER) return ONI_STATUS_NOT_SUPPORTED;
    const char serial[] = "SACCADE-VIRTUAL-0";
    if (*size < static_cast<int>(sizeof(serial))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(data, serial, sizeof(serial));
    *size = sizeof(serial);
    return ONI_STATUS_OK;
  }
  OniStatus setProperty(int id, const void* data, int size) override {
    if (id != ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || size != sizeof(OniImageRegistrationMode))
      return ONI_STATUS_NOT_SUPPORTED;
    const auto mode = *static_cast<const OniImageRegistrationMode*>(data);
    if (!isImageRegistrationModeSupported(mode)) return ONI_STATUS_NOT_SUPPORTED;
    state_.registered = mode == ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR;
    return ONI_STATUS_OK;
  }
  OniBool isPropertySupported(int id) override {
    return id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER ||
           (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION && !state_.recording.registered.empty());
  }
  OniBool isImageRegistrationModeSupported(OniImageRegistrationMode mode) override {
    return mode == ONI_IMAGE_REGISTRATION_OFF ||
           (mode == ONI_IMAGE_REGISTRATION_DEPTH_TO_COLOR && !state_.recording.registered.empty());
  }

 private:
  DeviceState state_;
  OniVideoMode modes_[2];
  OniSensorInfo sensors_[2];
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
    Announce(dir);
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
  // A folder named by URI (saccade-virtual://DIR) that SACCADE_VIRTUAL_DEVICE did not name
  // becomes a device too, as an .oni path does for the file driver.
  OniStatus tryDevice(const char* uri) override {
    if (std::strncmp(uri, kUriPrefix, std::strlen(kUriPrefix)) != 0) return ONI_STATUS_ERROR;
    Announce(uri + std::strlen(kUriPrefix));
    return ONI_STATUS_OK;
  }

 private:
  void Announce(const char* dir) {
    OniDeviceInfo info{};
    std::snprintf(info.uri, sizeof(info.uri), "%s%s", kUriPrefix, dir);
    std::snprintf(info.vendor, sizeof(info.vendor), "Saccade");
    std::snprintf(info.name, sizeof(info.name), "Virtual depth and colour camera");
    deviceConnected(&info);
  }
};

}  // namespace

ONI_EXPORT_DRIVER(VirtualDriver)
