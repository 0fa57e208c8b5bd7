#include "io/sources/freenect_source.h"

#include "io/sources/camera_source.h"

#include "core/fail.h"
#include "core/registration.h"
#include "io/formats/fakenect_dump.h"
#include "io/formats/images.h"
#include "io/sources/frame_pairer.h"

#include <libfreenect.h>

#include <sys/time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace saccade {

namespace {

using Clock = std::chrono::steady_clock;

// Half a frame period at 30 Hz, in ticks of the Kinect's 60 MHz clock.
constexpr std::int64_t kPairingTolerance = static_cast<std::int64_t>(kKinectClockHz / 60);

class FreenectSource : public CameraSource {
 public:
  ~FreenectSource() override {
    Stop();
    if (worker_.joinable()) worker_.join();
    Disconnect();
    if (context_) freenect_shutdown(context_);
  }

  bool Open(const std::string& device, const FreenectOptions& options, double wait_at_start_s,
            std::string* error) {
    device_spec_ = device;
    raw_only_ = options.raw;
    calibration_ = NominalKinectCalibration();
    if (!options.calibration.empty()) {
      ColourCameraFile file;
      if (!ReadColourCameraFile(options.calibration, &file, error)) return false;
      const IntrinsicsFile& k = file.intrinsics;
      if (k.width != kKinectWidth || k.height != kKinectHeight)
        return Fail(error, options.calibration + ": describes a " + std::to_string(k.width) + "x" +
                               std::to_string(k.height) + " colour camera; a Kinect's is 640x480");
      calibration_.colour = k.Camera();
      calibration_.colour_from_depth = ColourFromDepth(file.t, file.r);
    }
    // fakenect exits the process on a file it cannot open: check its dump whole first.
    const char* replay = std::getenv("FAKENECT_PATH");
    if (replay && *replay) {
      replay_dir_ = replay;
      if (!CheckFakenectDump(replay_dir_, &replay_frames_, error)) return false;
    }
    if (freenect_init(&context_, nullptr) < 0) {
      context_ = nullptr;
      return Fail(error, Spec() +
                             ": libfreenect cannot start (can libusb open the USB devices? "
                             "docs/SOURCES.md says which udev rules and groups)");
    }
    freenect_set_log_level(context_, FREENECT_LOG_FATAL);  // its errors come back as ours
    freenect_select_subdevices(context_, FREENECT_DEVICE_CAMERA);
    std::string why;
    const bool opened = Connect(&why);
    if (!opened && !StartWaiting(why, wait_at_start_s)) return Fail(error, why);
    worker_ = std::thread([this, opened] { Run(!opened); });
    return true;
  }

  SourceStats Stats() const override {
    SourceStats s = BaseStats();
    s.unpaired = unpaired_;  // copied from the pairer by the worker
    return s;
  }

  // A replay is played whole, none of it lost; a Kinect runs at its own pace.
  bool Live() const override { return replay_dir_.empty(); }

  std::string Describe() const override {
    if (!replay_dir_.empty())
      return Spec() + " (fakenect replay of " + replay_dir_ + ", " +
             std::to_string(replay_frames_) + " depth frames, raw disparity)";
    return Spec() + " (Kinect v1, " +
           (registered_ ? "depth registered by the device"
                        : "raw disparity registered by Saccade") +
           ")";
  }

 private:
  std::string Spec() const { return "freenect://" + device_spec_; }

  // The mode of `format` at 640x480 among those the library offers (fakenect offers only the
  // raw ones, and aborts when asked for another, so the modes are listed rather than found).
  static std::optional<freenect_frame_mode> DepthMode(freenect_depth_format format) {
    for (int i = 0; i < freenect_get_depth_mode_count(); ++i) {
      const freenect_frame_mode m = freenect_get_depth_mode(i);
      if (m.is_valid && m.resolution == FREENECT_RESOLUTION_MEDIUM && m.depth_format == format)
        return m;
    }
    return std::nullopt;
  }
  static std::optional<freenect_frame_mode> RgbMode() {
    for (int i = 0; i < freenect_get_video_mode_count(); ++i) {
      const freenect_frame_mode m = freenect_get_video_mode(i);
      if (m.is_valid && m.resolution == FREENECT_RESOLUTION_MEDIUM &&
          m.video_format == FREENECT_VIDEO_RGB)
        return m;
    }
    return std::nullopt;
  }

  // Opens the device and starts both streams; false with why not (closed again).
  bool Connect(std::string* why) {
    const int found = freenect_num_devices(context_);
    if (found <= 0)
      return Fail(why, Spec() +
                           ": no Kinect found (libfreenect lists none; is it plugged in, "
                           "powered, and readable by this user?)");
    const bool by_index = std::all_of(device_spec_.begin(), device_spec_.end(),
                                      [](char c) { return c >= '0' && c <= '9'; });
    int rc = 0;
    if (by_index) {
      const int index = device_spec_.empty() ? 0 : std::atoi(device_spec_.c_str());
      if (device_spec_.size() > 3 || index >= found)
        return Fail(why, Spec() + ": no such device; " + std::to_string(found) +
                             " found (freenect://0 is the first)");
      rc = freenect_open_device(context_, &device_, index);
    } else {
      rc = freenect_open_device_by_camera_serial(context_, &device_, device_spec_.c_str());
    }
    if (rc < 0) {
      device_ = nullptr;
      if (!by_index && replay_dir_.empty()) {  // (fakenect has no device list)
        std::string serials;
        freenect_device_attributes* list = nullptr;
        if (freenect_list_device_attributes(context_, &list) >= 0) {
          for (auto* a = list; a; a = a->next)
            serials += (serials.empty() ? "" : ", ") + std::string(a->camera_serial);
          freenect_free_device_attributes(list);
        }
        return Fail(why, Spec() + ": no Kinect with that serial number, or it is in use (found: " +
                             (serials.empty() ? "none" : serials) + ")");
      }
      return Fail(why, Spec() + ": cannot open the Kinect (libfreenect error " +
                           std::to_string(rc) + "; is another program using it?)");
    }
    std::optional<freenect_frame_mode> depth =
        raw_only_ ? std::nullopt : DepthMode(FREENECT_DEPTH_REGISTERED);
    registered_ = depth.has_value();
    if (!depth) depth = DepthMode(FREENECT_DEPTH_11BIT);
    const std::optional<freenect_frame_mode> video = RgbMode();
    if (!depth || !video) {
      Disconnect();
      return Fail(
          why, Spec() + ": libfreenect offers no 640x480 " + (depth ? "RGB" : "depth") + " mode");
    }
    freenect_set_user(device_, this);
    freenect_set_depth_callback(device_, &FreenectSource::OnDepth);
    freenect_set_video_callback(device_, &FreenectSource::OnVideo);
    if (freenect_set_depth_mode(device_, *depth) < 0 ||
        freenect_set_video_mode(device_, *video) < 0 || freenect_start_depth(device_) < 0 ||
        freenect_start_video(device_) < 0) {
      Disconnect();
      return Fail(why, Spec() + ": cannot start the Kinect's depth and colour streams");
    }
    pairer_.Clear();
    clock_started_ = false;  // a replugged Kinect's clock starts anew
    last_frame_ = Clock::now();
    return true;
  }

  void Disconnect() {
    if (!device_) return;
    freenect_stop_depth(device_);
    freenect_stop_video(device_);
    freenect_close_device(device_);
    device_ = nullptr;
  }

  // The worker: libfreenect's event loop (callbacks come from it, on this thread), and
  // reconnection with back-off when the device is missing, silent or failing.
  void Run(bool waiting) {
    auto backoff = std::chrono::milliseconds(500);
    while (!stopped_) {
      if (!device_) {
        std::string why;
        if (Connect(&why)) {
          if (!waiting) ++reconnects_;
          waiting = false;
          backoff = std::chrono::milliseconds(500);
          SetState("streaming");
          continue;
        }
        std::unique_lock<std::mutex> lock(wake_mutex_);
        if (!BackOff(waiting, why, &backoff, &lock)) return;
        continue;
      }
      timeval timeout{0, 100000};
      const int rc = freenect_process_events_timeout(context_, &timeout);
      if (rc < 0 && !replay_dir_.empty()) {  // fakenect: the dump is over
        FlushPending();
        SetState("ended");
        mailbox_.Close();
        return;
      }
      // A replay waits for its reader (Deliver) and keeps the dump's own gaps: no stall there.
      if (rc < 0 || (replay_dir_.empty() && Clock::now() - last_frame_ > std::chrono::seconds(2))) {
        Disconnect();
        SetState(rc < 0 ? "reconnecting: libfreenect error " + std::to_string(rc)
                        : "reconnecting: no frame for 2 s");
      }
    }
  }

  static void OnDepth(freenect_device* device, void* data, std::uint32_t timestamp) {
    static_cast<FreenectSource*>(freenect_get_user(device))->Depth(data, timestamp);
  }
  static void OnVideo(freenect_device* device, void* data, std::uint32_t timestamp) {
    static_cast<FreenectSource*>(freenect_get_user(device))->Video(data, timestamp);
  }

  // The Kinect's 32-bit timestamp, unwrapped: the first is taken as it is, later ones step by
  // their signed difference (depth and colour frames may come slightly out of order).
  std::int64_t Unwrap(std::uint32_t timestamp) {
    if (!clock_started_) {
      clock_started_ = true;
      ticks_ = timestamp;
    } else {
      ticks_ += static_cast<std::int32_t>(timestamp - last_timestamp_);
    }
    last_timestamp_ = timestamp;
    return ticks_;
  }

  struct Image {
    std::vector<std::uint16_t> depth;  // millimetres (registered) or raw disparity
    std::vector<std::uint8_t> rgb;
    std::int64_t ticks = 0;
  };

  void Depth(void* data, std::uint32_t timestamp) {
    last_frame_ = Clock::now();
    Image image;
    // fakenect hands over its file's bytes after the header: not always 2-byte aligned.
    image.depth.resize(kKinectWidth * kKinectHeight);
    std::memcpy(image.depth.data(), data, image.depth.size() * sizeof(std::uint16_t));
    image.ticks = Unwrap(timestamp);
    const std::int64_t ticks = image.ticks;
    pairer_.AddDepth(std::move(image), ticks);
  }

  void Video(void* data, std::uint32_t timestamp) {
    Image image;
    const auto* pixels = static_cast<const std::uint8_t*>(data);
    image.rgb.assign(pixels, pixels + kKinectWidth * kKinectHeight * 3);
    image.ticks = Unwrap(timestamp);
    const std::int64_t ticks = image.ticks;
    pairer_.AddColour(std::move(image), ticks);
  }

  void FlushPending() { pairer_.Flush(); }

  // A depth frame, with its colour when paired, as a cloud in the colour camera's frame.
  void Deliver(const Image& depth, const Image* rgb) {
    Item item;
    const CameraIntrinsics& k = calibration_.colour;
    const std::uint8_t* colour = rgb ? rgb->rgb.data() : nullptr;
    if (registered_) {
      item.frame.cloud = std::make_shared<const Cloud>(DepthToCloud(depth.depth.data(), colour, k));
    } else {
      std::vector<std::uint16_t> mm(depth.depth.size());
      for (std::size_t i = 0; i < mm.size(); ++i) mm[i] = KinectDisparityToMm(depth.depth[i]);
      const auto seen =
          RegisterDepth(mm.data(), calibration_.depth, calibration_.colour_from_depth, k);
      item.frame.cloud = std::make_shared<const Cloud>(DepthToCloud(seen.data(), colour, k));
    }
    item.frame.intrinsics = k;
    item.frame.capture_utime =
        static_cast<std::int64_t>(std::llround(depth.ticks / (kKinectClockHz / 1e6)));
    item.frame.sequence = sequence_++;
    item.frame.arrival_steady_ns = SteadyNowNs();
    ++produced_;
    unpaired_ = pairer_.unpaired();
    if (!replay_dir_.empty()) mailbox_.WaitUntilTaken();  // a replay loses nothing
    mailbox_.Put(std::move(item));
  }

  std::string device_spec_;
  bool raw_only_ = false;
  ColourCalibration calibration_;
  std::string replay_dir_;  // FAKENECT_PATH when replaying
  int replay_frames_ = 0;
  freenect_context* context_ = nullptr;
  freenect_device* device_ = nullptr;
  std::atomic<bool> registered_{false};  // the device registers depth to colour (millimetres)
  // The worker's own state: pairing (half a frame period) and the unwrapped clock.
  FramePairer<Image, Image> pairer_{
      kPairingTolerance,
      [this](const Image& depth, const Image* colour) { Deliver(depth, colour); }};
  bool clock_started_ = false;
  std::uint32_t last_timestamp_ = 0;
  std::int64_t ticks_ = 0;
  std::uint64_t sequence_ = 0;
  Clock::time_point last_frame_;
  std::atomic<std::uint64_t> unpaired_{0};  // as pairer_'s, for Stats()
  std::thread worker_;
};

}  // namespace

std::unique_ptr<FrameSource> OpenFreenectDevice(const std::string& device,
                                                const FreenectOptions& options,
                                                double wait_at_start_s, std::string* error) {
  auto source = std::make_unique<FreenectSource>();
  if (!source->Open(device, options, wait_at_start_s, error)) return nullptr;
  return source;
}

}  // namespace saccade
