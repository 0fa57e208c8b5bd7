#include "io/sources/openni2_stream.h"

#include "core/fail.h"
#include "io/base/log.h"
#include "io/formats/images.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

namespace saccade::openni2_internal {

std::string LastOpenNIError() {
  const char* e = openni::OpenNI::getExtendedError();
  std::string s = e && *e ? e : "no detail from libOpenNI2";
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ' ';
  return s;
}

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

namespace {

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

}  // namespace

SourceStats StreamSource::Stats() const {
  SourceStats s = BaseStats();
  s.dropped += skipped_;
  std::lock_guard<std::mutex> lock(pair_mutex_);
  s.unpaired = pairer_.unpaired();
  return s;
}

bool StreamSource::StartRecording(const std::string& path, std::string* error) {
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

void StreamSource::StopRecording() {
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
    if (now >= give_up || !callback_.wait_until(calls, std::min(now + kDrainAtMost, give_up), [&] {
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

bool StreamSource::OpenStream(const std::string& uri, bool live, std::string* error) {
  if (device_.open(uri.c_str()) != openni::STATUS_OK)
    return Fail(error, uri + ": cannot open: " + LastOpenNIError());
  if (!device_.hasSensor(openni::SENSOR_DEPTH))
    return Fail(error, uri + ": no depth stream: " + LastOpenNIError());
  using Registration = ColourOptions::Registration;
  const bool colour = colour_options_.enabled && device_.hasSensor(openni::SENSOR_COLOR);
  Registration registration = colour_options_.registration;
  if (colour) {
    const bool offered =
        live && device_.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR);
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

bool StreamSource::StartStream(std::string* error) {
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

void StreamSource::CloseStream() {
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

void StreamSource::RemoveListeners() {
  if (depth_.isValid()) depth_.removeNewFrameListener(&depth_listener_);
  if (colour_.isValid()) colour_.removeNewFrameListener(&colour_listener_);
  std::lock_guard<std::mutex> calls(callback_mutex_);
  depth_listener_.listening = colour_listener_.listening = false;
}

bool StreamSource::ReadAndPair(bool depth, const Sink& sink) {
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

void StreamSource::FlushPending(const Sink& sink) {
  std::unique_lock<std::mutex> lock(pair_mutex_);
  pairer_.Flush();
  Emit(&lock, sink);
}

bool StreamSource::HasPending() const {
  std::lock_guard<std::mutex> lock(pair_mutex_);
  return pairer_.waiting();
}

void StreamSource::Listen(openni::VideoStream* stream, Listener* listener) {
  {
    std::lock_guard<std::mutex> calls(callback_mutex_);
    listener->listening = true;
  }
  stream->addNewFrameListener(listener);
}

bool StreamSource::ChooseRgbMode(const openni::VideoMode& depth) {
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
      now.getResolutionY() == modes[best].getResolutionY() && now.getFps() == modes[best].getFps())
    return true;
  return colour_.setVideoMode(modes[best]) == openni::STATUS_OK;
}

void StreamSource::ResetPairing() {
  std::lock_guard<std::mutex> lock(pair_mutex_);
  pairer_.Clear();
}

void StreamSource::Emit(std::unique_lock<std::mutex>* lock, const Sink& sink) {
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

}  // namespace saccade::openni2_internal
