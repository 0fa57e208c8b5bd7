#include "io/sources/openni2_source.h"

#include "core/fail.h"

#include "core/registration.h"
#include "io/base/log.h"
#include "io/base/text.h"
#include "io/formats/images.h"
#include "io/sources/frame_pairer.h"
#include "io/sources/mailbox.h"

#include <OpenNI.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

extern char** environ;

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

// saccade-oni-check beside the running program (an installed layout), else the build's.
std::string OniCheckBinary() {
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    std::string dir(self, static_cast<std::size_t>(n));
    dir.erase(dir.rfind('/') + 1);
    if (access((dir + "saccade-oni-check").c_str(), X_OK) == 0) return dir + "saccade-oni-check";
  }
  return SACCADE_ONI_CHECK_BINARY;
}

// Plays the recording to its end in a child process (saccade-oni-check) before this process
// opens it: Debian's .oni driver crashes on crafted files (a string length or property record
// that lies, a corrupt frame), and a crash there must not take Saccade with it. The child has
// 30 s plus 1 s per 10 MB of file, in a process group of its own with no signal blocked (a
// daemon's signal thread blocks SIGTERM and the like, and a child inherits that); its stderr
// line is the reason when it refuses the file.
bool CheckOniRecording(const std::string& path, std::string* error) {
  std::uint64_t size = 0;
  if (!StatRegularFile(path, "a recording", &size, error)) return false;
  const std::string checker = OniCheckBinary();
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0)
    return Fail(error, path + ": cannot check the recording: " + std::strerror(errno));
  fcntl(out[0], F_SETFL, O_NONBLOCK);  // a grandchild keeping stderr open must not block us
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 2);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &all);
  posix_spawnattr_setpgroup(&attributes, 0);
  posix_spawnattr_setflags(&attributes,
                           POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  char* argv[] = {const_cast<char*>(checker.c_str()), const_cast<char*>(path.c_str()), nullptr};
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, checker.c_str(), &actions, &attributes, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(out[1]);
  if (rc != 0) {
    close(out[0]);
    return Fail(error,
                path + ": cannot check the recording (" + checker + "): " + std::strerror(rc));
  }
  // Its stderr, until the child has ended or the time is up (then its group is killed).
  const auto limit = std::chrono::seconds(30 + size / (10 << 20));
  const auto deadline = std::chrono::steady_clock::now() + limit;
  std::string said;
  const auto drain = [&] {
    char buffer[512];
    ssize_t got;
    while ((got = read(out[0], buffer, sizeof buffer)) > 0)
      if (said.size() < 4096) said.append(buffer, static_cast<std::size_t>(got));
    return got == 0;  // end of file
  };
  int status = 0;
  bool ended = false, closed = false;
  while (!ended) {
    const pid_t waited = waitpid(pid, &status, WNOHANG);
    if (waited == pid || (waited < 0 && errno != EINTR)) {
      ended = waited == pid;
      break;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{closed ? -1 : out[0], POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 100))) < 0 && errno != EINTR)
      break;
    if (p.revents != 0) closed = drain();
  }
  drain();
  close(out[0]);
  if (!ended) {
    kill(-pid, SIGKILL);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return Fail(error, path + ": libOpenNI2 did not finish playing it in " +
                           std::to_string(limit.count()) + " s; refused");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return true;
  // Refused: its one line, which names the file. Anything else is a crash: a signal, or (in a
  // sanitized build) the sanitizer that caught it ending the child with its report.
  said = said.substr(0, said.find('\n'));
  if (WIFEXITED(status) && WEXITSTATUS(status) == 1 && said.rfind(path + ": ", 0) == 0)
    return Fail(error, said);
  const std::string how = WIFSIGNALED(status) ? strsignal(WTERMSIG(status))
                                              : "exit " + std::to_string(WEXITSTATUS(status));
  return Fail(error, path + ": libOpenNI2 crashed playing it (" + how +
                         "): a corrupt or crafted recording; refused");
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

// A stream's pixels packed row after row (repacked when the stream pads its rows); nullptr
// when the frame's stride or data size cannot hold its rows (a corrupt recording).
template <typename T>
const T* Packed(const openni::VideoFrameRef& ref, int channels, std::vector<T>* repacked) {
  const int row_bytes = ref.getWidth() * channels * static_cast<int>(sizeof(T));
  if (ref.getWidth() <= 0 || ref.getHeight() <= 0 || ref.getStrideInBytes() < row_bytes ||
      static_cast<std::int64_t>(ref.getDataSize()) <
          static_cast<std::int64_t>(ref.getStrideInBytes()) * (ref.getHeight() - 1) + row_bytes)
    return nullptr;
  if (ref.getStrideInBytes() == row_bytes) return static_cast<const T*>(ref.getData());
  repacked->resize(static_cast<std::size_t>(ref.getWidth()) * ref.getHeight() * channels);
  const auto* bytes = static_cast<const std::uint8_t*>(ref.getData());
  for (int v = 0; v < ref.getHeight(); ++v)
    std::memcpy(repacked->data() + static_cast<std::size_t>(v) * ref.getWidth() * channels,
                bytes + static_cast<std::size_t>(v) * ref.getStrideInBytes(), row_bytes);
  return repacked->data();
}

// How a depth frame becomes a cloud: the depth camera, and where colour comes from.
struct Conversion {
  CameraIntrinsics depth;        // the depth stream's camera
  bool register_colour = false;  // Saccade's registration: the depth moved into `colour`
  ColourCalibration calibration;
};

// A depth frame (and its colour frame, when paired) as a cloud in metres.
bool ToFrame(const openni::VideoFrameRef& ref, const openni::VideoFrameRef* colour,
             const Conversion& c, Frame* frame, std::string* error) {
  const CameraIntrinsics& k = c.depth;
  const auto format = ref.getVideoMode().getPixelFormat();
  if (format != openni::PIXEL_FORMAT_DEPTH_1_MM && format != openni::PIXEL_FORMAT_DEPTH_100_UM)
    return Fail(error, "OpenNI2 stream: not a depth format (" + std::to_string(format) + ")");
  if (ref.getWidth() != k.width || ref.getHeight() != k.height || ref.getCropOriginX() != 0)
    return Fail(error, "OpenNI2 stream: frame size differs from the stream's video mode");
  std::vector<std::uint16_t> repacked;
  const std::uint16_t* data = Packed(ref, 1, &repacked);
  if (!data) return Fail(error, "OpenNI2 stream: a depth frame shorter than its rows");
  if (format == openni::PIXEL_FORMAT_DEPTH_100_UM) {
    if (repacked.empty())
      repacked.assign(data, data + static_cast<std::size_t>(k.width) * k.height);
    for (auto& d : repacked) d = static_cast<std::uint16_t>(d / 10);
    data = repacked.data();
  }
  const CameraIntrinsics& out_k = c.register_colour ? c.calibration.colour : k;
  std::vector<std::uint8_t> rgb_repacked;
  const std::uint8_t* rgb = nullptr;
  if (colour) {
    if (colour->getVideoMode().getPixelFormat() != openni::PIXEL_FORMAT_RGB888)
      return Fail(error, "OpenNI2 colour stream: not RGB888");
    if (colour->getWidth() != out_k.width || colour->getHeight() != out_k.height)
      return Fail(error, "OpenNI2 colour stream: a " + std::to_string(colour->getWidth()) + "x" +
                             std::to_string(colour->getHeight()) + " frame where " +
                             std::to_string(out_k.width) + "x" + std::to_string(out_k.height) +
                             " was set up");
    rgb = Packed(*colour, 3, &rgb_repacked);
    if (!rgb) return Fail(error, "OpenNI2 colour stream: a frame shorter than its rows");
  }
  frame->intrinsics = out_k;
  if (c.register_colour) {
    const auto registered =
        RegisterDepth(data, k, c.calibration.colour_from_depth, c.calibration.colour);
    frame->cloud = std::make_shared<const Cloud>(DepthToCloud(registered.data(), rgb, out_k));
  } else {
    frame->cloud = std::make_shared<const Cloud>(DepthToCloud(data, rgb, k));
  }
  frame->capture_utime = static_cast<std::int64_t>(ref.getTimestamp());
  return true;
}

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

// What the device and playback sources share: the depth stream and the colour stream beside
// it, a recorder, the pairing of their frames, the mailbox that OpenNI2's callback threads fill,
// and the counters.
class StreamSource : public OpenNI2Source {
 public:
  explicit StreamSource(const ColourOptions& colour) : colour_options_(colour) {}
  // Each derived class stops and closes the streams in its own destructor, while OnFrame
  // still resolves to it; by the time this one runs the streams are closed.
  ~StreamSource() override = default;

  SourceStats Stats() const override {
    SourceStats s = BaseStats();
    s.dropped += skipped_;
    std::lock_guard<std::mutex> lock(pair_mutex_);
    s.unpaired = pairer_.unpaired();
    return s;
  }

  bool StartRecording(const std::string& path, std::string* error) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (recorder_.isValid()) return Fail(error, path + ": already recording");
    if (recorder_.create(path.c_str()) != openni::STATUS_OK ||
        recorder_.attach(depth_) != openni::STATUS_OK ||
        (colour_.isValid() && recorder_.attach(colour_) != openni::STATUS_OK) ||
        recorder_.start() != openni::STATUS_OK) {
      recorder_.destroy();
      return Fail(error, path + ": cannot record: " + LastOpenNIError());
    }
    return true;
  }

  // libOpenNI2 (2.2) can deadlock destroying a recorder while frames arrive: a stream's frame
  // thread, once past the recorder's started check, takes the stream's recorder lock and then
  // the recorder's stream lock (Recorder::record); destroy() takes them the other way round
  // (detachAllStreams). Seen as a hang of the .oni recording test on a loaded machine, every
  // thread waiting in libOpenNI2. After stop() no frame passes that check, so destroy() waits
  // until every stream being listened to has called back kCallbacksAfterStop more times. A
  // stream's frames come one at a time and wake its callback thread once recorded; the third
  // call after stop() was woken by a frame that came after stop(), so the one that may have
  // been past the check has left the locks. While callbacks come it waits on (a frame may be
  // held up behind the recorder's thread writing the file); once no stream has called back for
  // kDrainAtMost they have stalled, and it goes on (and after kDrainLongest in all whatever
  // comes: one stream may flow while the other has stalled). Going on unconfirmed is logged:
  // silence is not proof, a driver thread can be held in Recorder::record behind the
  // recorder's thread writing a frame, and then destroy() can still deadlock in libOpenNI2.
  // Not covered: stop() right after start(), before libOpenNI2's recorder thread has taken the
  // start (it sets started then, after this stop()); step-mode playback, whose frames are read,
  // not listened to (the player's frame in flight is not waited for).
  void StopRecording() override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!recorder_.isValid()) return;
    recorder_.stop();
    std::unique_lock<std::mutex> calls(callback_mutex_);
    const std::uint64_t depth_then = depth_listener_.calls, colour_then = colour_listener_.calls;
    const auto drained = [&] {
      const auto done = [](const Listener& l, std::uint64_t then) {
        return !l.listening || l.calls >= then + kCallbacksAfterStop;
      };
      return done(depth_listener_, depth_then) && done(colour_listener_, colour_then);
    };
    const Clock::time_point give_up = Clock::now() + kDrainLongest;  // one stream may stall
    while (!drained()) {
      const Clock::time_point now = Clock::now();
      const std::uint64_t seen = depth_listener_.calls + colour_listener_.calls;
      if (now >= give_up ||
          !callback_.wait_until(calls, std::min(now + kDrainAtMost, give_up), [&] {
            return drained() || depth_listener_.calls + colour_listener_.calls != seen;
          }))
        break;  // stalled, or out of time
    }
    const bool confirmed = drained();
    calls.unlock();
    if (!confirmed)
      Log(LogLevel::kWarning,
          "OpenNI2: closing the recording before every stream's frames were seen through "
          "(a stream stalled); libOpenNI2's recorder may hang here");
    recorder_.destroy();
  }

 protected:
  // Opens `uri`, its depth stream and, when asked and there, its colour stream with the
  // registration the options choose (`live`: a device, which may register; else a recording).
  bool OpenStream(const std::string& uri, bool live, std::string* error) {
    if (device_.open(uri.c_str()) != openni::STATUS_OK)
      return Fail(error, uri + ": cannot open: " + LastOpenNIError());
    if (!device_.hasSensor(openni::SENSOR_DEPTH))
      return Fail(error, uri + ": no depth stream: " + LastOpenNIError());
    using Registration = ColourOptions::Registration;
    const bool colour = colour_options_.enabled && device_.hasSensor(openni::SENSOR_COLOR);
    Registration registration = colour_options_.registration;
    if (colour) {
      const bool offered = live && device_.isImageRegistrationModeSupported(
                                       openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR);
      const bool calibrated = !colour_options_.calibration.empty();
      if (registration == Registration::kAuto)  // a calibration given asks for Saccade's
        registration = calibrated ? Registration::kSaccade
                       : !live    ? Registration::kNone
                       : offered  ? Registration::kDevice
                                  : Registration::kSaccade;
      if (calibrated && registration != Registration::kSaccade)
        return Fail(error, uri +
                               ": calibration= is for Saccade's registration "
                               "(registration=saccade or auto)");
      if (registration == Registration::kDevice && !live)
        return Fail(error, uri +
                               ": a recording cannot register on a device: its frames are "
                               "as recorded (registration=none, or saccade with calibration=)");
      if (registration == Registration::kDevice && !offered)
        return Fail(error, uri +
                               ": the device offers no depth-to-colour registration "
                               "(registration=saccade registers with Saccade's own)");
      const auto mode = registration == Registration::kDevice
                            ? openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR
                            : openni::IMAGE_REGISTRATION_OFF;
      if (live && device_.getImageRegistrationMode() != mode &&
          device_.setImageRegistrationMode(mode) != openni::STATUS_OK)
        return Fail(error, uri + ": cannot set image registration: " + LastOpenNIError());
    }
    if (depth_.create(device_, openni::SENSOR_DEPTH) != openni::STATUS_OK)
      return Fail(error, uri + ": no depth stream: " + LastOpenNIError());
    // A mirrored image (a driver's .ini can set it) would flip the baseline's side.
    if (live) depth_.setMirroringEnabled(false);
    conversion_ = Conversion{};
    conversion_.depth = IntrinsicsOf(depth_);
    const openni::VideoMode depth_mode = depth_.getVideoMode();
    const int fps = depth_mode.getFps() > 0 ? depth_mode.getFps() : 30;
    {
      std::lock_guard<std::mutex> lock(pair_mutex_);
      pairer_.set_tolerance(1000000 / (2 * fps));  // half a depth frame period, microseconds
    }
    if (!colour) return true;
    if (colour_.create(device_, openni::SENSOR_COLOR) != openni::STATUS_OK)
      return Fail(error, uri + ": cannot open the colour stream: " + LastOpenNIError());
    if (live && !ChooseRgbMode(depth_mode))
      return Fail(error, uri + ": the colour stream has no RGB888 mode");
    if (live) colour_.setMirroringEnabled(false);
    const openni::VideoMode colour_mode = colour_.getVideoMode();
    if (colour_mode.getPixelFormat() != openni::PIXEL_FORMAT_RGB888)
      return Fail(error, uri + ": the colour stream is not RGB888 (format " +
                             std::to_string(colour_mode.getPixelFormat()) + ")");
    const std::string colour_size = std::to_string(colour_mode.getResolutionX()) + "x" +
                                    std::to_string(colour_mode.getResolutionY());
    if (registration != Registration::kSaccade) {
      if (colour_mode.getResolutionX() != depth_mode.getResolutionX() ||
          colour_mode.getResolutionY() != depth_mode.getResolutionY())
        return Fail(error, uri + ": the colour stream is " + colour_size + " and the depth " +
                               std::to_string(depth_mode.getResolutionX()) + "x" +
                               std::to_string(depth_mode.getResolutionY()) +
                               ": colour taken pixel for pixel needs one size "
                               "(registration=saccade registers across sizes)");
      return true;
    }
    conversion_.register_colour = true;
    ColourCalibration& calibration = conversion_.calibration;
    calibration.depth = conversion_.depth;
    if (colour_options_.calibration.empty()) {
      calibration.colour = IntrinsicsOf(colour_);
      calibration.colour_from_depth = NominalKinectCalibration().colour_from_depth;
      return true;
    }
    ColourCameraFile file;
    if (!ReadColourCameraFile(colour_options_.calibration, &file, error)) return false;
    const IntrinsicsFile& k = file.intrinsics;
    if (k.width != colour_mode.getResolutionX() || k.height != colour_mode.getResolutionY())
      return Fail(error, colour_options_.calibration + ": describes a " + std::to_string(k.width) +
                             "x" + std::to_string(k.height) + " colour camera, the stream is " +
                             colour_size);
    calibration.colour = k.Camera();
    calibration.colour_from_depth = ColourFromDepth(file.t, file.r);
    return true;
  }

  bool StartStream(std::string* error) {
    ResetPairing();
    Listen(&depth_, &depth_listener_);
    if (colour_.isValid()) Listen(&colour_, &colour_listener_);
    if (depth_.start() != openni::STATUS_OK ||
        (colour_.isValid() && colour_.start() != openni::STATUS_OK)) {
      RemoveListeners();
      return Fail(error, "cannot start the streams: " + LastOpenNIError());
    }
    return true;
  }

  void CloseStream() {
    StopRecording();
    RemoveListeners();
    ResetPairing();  // the frames held go back to their streams before the streams go
    { std::lock_guard<std::mutex> emitted(emit_mutex_); }  // and those being converted
    for (openni::VideoStream* stream : {&colour_, &depth_}) {
      if (!stream->isValid()) continue;
      stream->stop();
      stream->destroy();
    }
    if (device_.isValid()) device_.close();
  }

  // A new frame is ready on the depth stream (`depth`) or the colour stream; called from
  // OpenNI2's callback threads.
  virtual void OnFrame(bool depth) = 0;

  void RemoveListeners() {
    if (depth_.isValid()) depth_.removeNewFrameListener(&depth_listener_);
    if (colour_.isValid()) colour_.removeNewFrameListener(&colour_listener_);
    std::lock_guard<std::mutex> calls(callback_mutex_);
    depth_listener_.listening = colour_listener_.listening = false;
  }

  // Where delivered frames go, one at a time and in order.
  using Sink = std::function<void(Item)>;

  // Reads the frame the depth (`depth`) or colour stream has ready and pairs it; what is ready
  // to deliver goes to `sink`. Returns false (with an error item to `sink`) when it cannot read.
  bool ReadAndPair(bool depth, const Sink& sink) {
    openni::VideoFrameRef ref;
    if ((depth ? depth_ : colour_).readFrame(&ref) != openni::STATUS_OK) {
      Item item;
      item.ok = false;
      item.error = "OpenNI2 stream: cannot read a frame: " + LastOpenNIError();
      sink(std::move(item));
      return false;
    }
    std::unique_lock<std::mutex> lock(pair_mutex_);
    if (!depth) {
      pairer_.AddColour(ref, static_cast<std::int64_t>(ref.getTimestamp()));
    } else {
      if (last_index_ > 0 && ref.getFrameIndex() < last_index_) {  // a recording starts over
        if (stop_at_wrap_) {
          wrapped_ = true;  // not this playback's: it ends here
          Emit(&lock, sink);
          return true;
        }
        pairer_.Flush();  // the last pass's frames go out; its colours pair with no new frame
        pairer_.Clear();
      }
      // Frames libOpenNI2 skipped before reaching us count as dropped too.
      if (last_index_ > 0 && ref.getFrameIndex() > last_index_ + 1)
        skipped_ += static_cast<std::uint64_t>(ref.getFrameIndex() - last_index_ - 1);
      last_index_ = ref.getFrameIndex();
      if (colour_.isValid()) {
        pairer_.AddDepth(ref, static_cast<std::int64_t>(ref.getTimestamp()));
      } else {
        delivered_.push_back({ref, std::nullopt, sequence_++});
      }
    }
    Emit(&lock, sink);
    return true;
  }

  // Delivers the depth frames still waiting for their colour, uncoloured (the stream ended).
  void FlushPending(const Sink& sink) {
    std::unique_lock<std::mutex> lock(pair_mutex_);
    pairer_.Flush();
    Emit(&lock, sink);
  }
  bool HasPending() const {
    std::lock_guard<std::mutex> lock(pair_mutex_);
    return pairer_.waiting();
  }

  // One listener a stream: libOpenNI2 keeps one callback handle a listener, and hands it a
  // temporary VideoStream, so the listener itself says which stream it listens to.
  // Counts its calls for StopRecording.
  class Listener : public openni::VideoStream::NewFrameListener {
   public:
    Listener(StreamSource* owner, bool depth) : owner_(owner), depth_(depth) {}
    void onNewFrame(openni::VideoStream&) override {
      owner_->OnFrame(depth_);
      {
        std::lock_guard<std::mutex> lock(owner_->callback_mutex_);
        ++calls;
      }
      owner_->callback_.notify_all();
    }
    std::uint64_t calls = 0;  // guarded by the owner's callback_mutex_
    bool listening = false;   // likewise

   private:
    StreamSource* owner_;
    bool depth_;
  };

  void Listen(openni::VideoStream* stream, Listener* listener) {
    {
      std::lock_guard<std::mutex> calls(callback_mutex_);
      listener->listening = true;
    }
    stream->addNewFrameListener(listener);
  }

  static constexpr std::uint64_t kCallbacksAfterStop = 3;
  static constexpr std::chrono::milliseconds kDrainAtMost{1500};  // with no callback at all
  static constexpr std::chrono::seconds kDrainLongest{5};

  const ColourOptions colour_options_;
  Listener depth_listener_{this, true}, colour_listener_{this, false};
  openni::Device device_;
  openni::VideoStream depth_, colour_;
  openni::Recorder recorder_;
  std::mutex mutex_;           // the recorder
  std::mutex callback_mutex_;  // the listeners' counts, for StopRecording
  std::condition_variable callback_;
  std::atomic<std::uint64_t> skipped_{0};
  int last_index_ = 0;                // OpenNI2's own frame index of the last depth frame read
  bool stop_at_wrap_ = false;         // a playback that does not loop: set before streaming
  std::atomic<bool> wrapped_{false};  // such a playback met the recording's start again

 private:
  // A colour mode for a live device: RGB888 at the depth's size and rate when offered, else at
  // its size, else the largest. False when there is no RGB888 mode.
  bool ChooseRgbMode(const openni::VideoMode& depth) {
    const auto& modes = colour_.getSensorInfo().getSupportedVideoModes();
    const auto score = [&](const openni::VideoMode& m) {
      const bool size = m.getResolutionX() == depth.getResolutionX() &&
                        m.getResolutionY() == depth.getResolutionY();
      return (size ? 4 : 0) + (size && m.getFps() == depth.getFps() ? 2 : 0);
    };
    int best = -1;
    for (int i = 0; i < modes.getSize(); ++i) {
      if (modes[i].getPixelFormat() != openni::PIXEL_FORMAT_RGB888) continue;
      if (best < 0 || score(modes[i]) > score(modes[best]) ||
          (score(modes[i]) == score(modes[best]) &&
           modes[i].getResolutionX() > modes[best].getResolutionX()))
        best = i;
    }
    if (best < 0) return false;
    const openni::VideoMode now = colour_.getVideoMode();
    if (now.getPixelFormat() == openni::PIXEL_FORMAT_RGB888 &&
        now.getResolutionX() == modes[best].getResolutionX() &&
        now.getResolutionY() == modes[best].getResolutionY() &&
        now.getFps() == modes[best].getFps())
      return true;
    return colour_.setVideoMode(modes[best]) == openni::STATUS_OK;
  }

  void ResetPairing() {
    std::lock_guard<std::mutex> lock(pair_mutex_);
    pairer_.Clear();
  }

  // A depth frame the pairer delivered, with its colour frame or none, and its number.
  struct Paired {
    openni::VideoFrameRef depth;
    std::optional<openni::VideoFrameRef> colour;
    std::uint64_t sequence;
  };

  // Converts what the pairer delivered and hands it to `sink` outside the pairing lock (the
  // other stream's thread pairs on meanwhile), in pairing order: the emit lock is taken before
  // the pairing lock is let go.
  void Emit(std::unique_lock<std::mutex>* lock, const Sink& sink) {
    std::vector<Paired> paired;
    paired.swap(delivered_);
    // Even with nothing to emit: the caller then knows that what another thread paired before
    // it has been handed on (the end of a playback closes the mailbox after this).
    std::lock_guard<std::mutex> emitting(emit_mutex_);
    lock->unlock();
    for (const Paired& p : paired) {
      Item item;
      item.ok =
          ToFrame(p.depth, p.colour ? &*p.colour : nullptr, conversion_, &item.frame, &item.error);
      item.frame.sequence = p.sequence;
      item.frame.arrival_steady_ns = SteadyNowNs();
      ++produced_;
      sink(std::move(item));
    }
    paired.clear();  // the frames go back to their streams, which CloseStream keeps until here
  }

  Conversion conversion_;
  mutable std::mutex pair_mutex_;  // the pairing state below, from either stream's thread
  std::mutex emit_mutex_;          // held while delivered frames are converted and handed on
  FramePairer<openni::VideoFrameRef, openni::VideoFrameRef> pairer_{
      16666, [this](const openni::VideoFrameRef& depth, const openni::VideoFrameRef* colour) {
        delivered_.push_back({depth,
                              colour ? std::optional<openni::VideoFrameRef>(*colour) : std::nullopt,
                              sequence_++});
      }};
  std::vector<Paired> delivered_;  // what the pairer delivered during the current call
  std::uint64_t sequence_ = 0;
};

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

class PlaybackSource : public StreamSource {
 public:
  using StreamSource::StreamSource;
  bool Open(const std::string& path, const OniPlaybackOptions& options, std::string* error) {
    path_ = path;
    options_ = options;
    stop_at_wrap_ = !options.loop;
    if (!OpenStream(path, false, error)) return false;
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
      if (depth_.start() != openni::STATUS_OK ||
          (colour_.isValid() && colour_.start() != openni::STATUS_OK))
        return Fail(error, path + ": cannot start playback: " + LastOpenNIError());
      return true;
    }
    return StartStream(error);
  }

  ~PlaybackSource() override {
    Stop();
    StopRecording();  // while the listeners still count callbacks
    bool running = false;
    RemoveListeners();
    for (openni::VideoStream* stream : {&colour_, &depth_}) {
      if (!stream->isValid()) continue;
      stream->stop();
      running = true;
    }
    // libOniFile's player thread walks its stream list every 10 ms without a lock while no
    // stream runs; give it that beat to leave the walk before the streams are destroyed.
    if (running) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CloseStream();
  }

  Status Next(Frame* frame, std::string* error) override {
    if (options_.mode != OniPlaybackOptions::Mode::kStep) return StreamSource::Next(frame, error);
    // In manual playback the file driver reads the next frame of the file (of either stream)
    // when asked through waitForAnyStream (its manual trigger); a timeout keeps Stop()
    // responsive. After the last depth frame of a non-looping recording, a few more reads look
    // for its colour frame.
    int after_end = 0;
    const auto to_ready = [this](Item item) { ready_.push_back(std::move(item)); };
    while (ready_.empty()) {
      if (stopped_) return Status::kEnd;
      const bool at_end = !options_.loop && read_ >= frames_;
      if (at_end && (!HasPending() || after_end >= kReadsAfterEnd)) {
        FlushPending(to_ready);
        if (ready_.empty()) {
          SetState("ended");
          return Status::kEnd;
        }
        break;
      }
      openni::VideoStream* streams[] = {&depth_, &colour_};
      int ready = -1;
      const auto rc =
          openni::OpenNI::waitForAnyStream(streams, colour_.isValid() ? 2 : 1, &ready, 500);
      if (rc == openni::STATUS_TIME_OUT) continue;
      if (rc != openni::STATUS_OK) {
        Fail(error, path_ + ": playback failed: " + LastOpenNIError());
        return Status::kError;
      }
      if (at_end) {
        ++after_end;
        if (ready == 0) {  // the repeating player's next pass: not this playback's
          openni::VideoFrameRef skipped;
          depth_.readFrame(&skipped);
          continue;
        }
      } else if (ready == 0) {
        ++read_;
      }
      ReadAndPair(ready == 0, to_ready);
    }
    Item item = std::move(ready_.front());
    ready_.erase(ready_.begin());
    if (!item.ok) {
      Fail(error, path_ + ": " + item.error);
      return Status::kError;
    }
    *frame = std::move(item.frame);
    return Status::kFrame;
  }

  void OnFrame(bool depth) override {
    if (stopped_ || ended_) return;
    // The player repeats (see Open): a non-looping playback ends at the last frame, or at the
    // wrap when libOpenNI2 skipped the last frame in fast mode (ReadAndPair sees it and keeps
    // the next pass's first frame out).
    const auto put = [this](Item item) { mailbox_.Put(std::move(item)); };
    ReadAndPair(depth, put);
    if (depth && !options_.loop && (wrapped_ || last_index_ >= frames_)) {
      ended_ = true;
      FlushPending(put);
      SetState("ended");
      mailbox_.Close();
    }
  }
  bool Live() const override { return options_.mode != OniPlaybackOptions::Mode::kStep; }
  std::string Describe() const override {
    return path_ + " (" + std::to_string(frames_) + " frames" +
           (colour_.isValid() ? ", depth and colour)" : ")");
  }

 private:
  static constexpr int kReadsAfterEnd = 2;
  std::string path_;
  OniPlaybackOptions options_;
  int frames_ = 0;
  int read_ = 0;             // depth frames read in step mode
  std::vector<Item> ready_;  // step mode: frames paired and not yet returned
  std::atomic<bool> ended_{false};
};

}  // namespace

std::unique_ptr<OpenNI2Source> OpenOpenNI2Device(const std::string& device,
                                                 const ColourOptions& colour,
                                                 double wait_at_start_s, std::string* error) {
  if (!InitializeOpenNI(error)) return nullptr;
  auto source = std::make_unique<DeviceSource>(colour);
  if (!source->Open(device, wait_at_start_s, error)) return nullptr;
  return source;
}

std::unique_ptr<OpenNI2Source> OpenOniPlayback(const std::string& path,
                                               const OniPlaybackOptions& options,
                                               const ColourOptions& colour, std::string* error) {
  if (!CheckOniRecording(path, error) || !InitializeOpenNI(error)) return nullptr;
  auto source = std::make_unique<PlaybackSource>(colour);
  if (!source->Open(path, options, error)) return nullptr;
  return source;
}

}  // namespace saccade
