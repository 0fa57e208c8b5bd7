// OpenNI2 frame sources: live devices and .oni playback, through the real libOpenNI2.
#pragma once

#include "io/sources/camera_source.h"

#include <memory>
#include <string>

namespace saccade {

/// A FrameSource backed by an openni::VideoStream, which can also be recorded.
class OpenNI2Source : public CameraSource {
 public:
  /// Starts writing every frame the streams (depth, and colour when open) deliver to an .oni file
  /// (openni::Recorder) until the source is destroyed or StopRecording(). False with `error` when
  /// it cannot.
  virtual bool StartRecording(const std::string& oni_path, std::string* error) = 0;
  virtual void StopRecording() = 0;
};

/// How colour joins depth. Depth and colour frames are paired by timestamp
/// (io/sources/frame_pairer.h): a depth frame takes the colour frame nearest in time within half a
/// depth frame period; it waits for it while no more than 3 depth frames wait and the colour stream
/// has not passed its time; a depth frame left without one is delivered uncoloured and counted
/// (SourceStats::unpaired).
struct ColourOptions {
  bool enabled = true;  // open the colour stream when the device has one
  enum class Registration {
    kAuto,     // live: the device's when it offers it, else Saccade's; playback: kNone
    kDevice,   // the device's depth-to-colour registration; an error when it has none
    kSaccade,  // Saccade's: the depth moved into the colour camera (core/registration.h)
    kNone,     // colour taken pixel for pixel (the images are registered already)
  } registration = Registration::kAuto;
  /// A colour camera file (io/formats/images.h) for Saccade's registration; "" takes the colour
  /// camera's intrinsics from its field of view and puts it 25 mm right of the depth camera,
  /// parallel (NominalKinectCalibration's layout).
  std::string calibration;
};

/// `device`: "" for the first device, "#N" for the N-th (0-based), or a URI or serial number.
/// Live: frames go to a latest-frame mailbox from OpenNI2's callback thread; when no frame has
/// come for 2 s the device is closed and reopened with back-off (0.5 s doubling to 8 s). A
/// device that is not there at start fails at once with `wait_at_start_s` 0; with more, the
/// source opens and waits that long for it (Stats().state "waiting for device: why", the same
/// back-off), after which Next() returns the error.
std::unique_ptr<OpenNI2Source> OpenOpenNI2Device(const std::string& device,
                                                 const ColourOptions& colour,
                                                 double wait_at_start_s, std::string* error);

struct OniPlaybackOptions {
  enum class Mode {
    kRealtime,  // at the recorded pace, live: frames the consumer misses are dropped, counted
    kFast,      // as fast as libOpenNI2 reads them, live
    kStep,      // one frame per Next(), none lost
  } mode = Mode::kStep;
  bool loop = false;
};
std::unique_ptr<OpenNI2Source> OpenOniPlayback(const std::string& path,
                                               const OniPlaybackOptions& options,
                                               const ColourOptions& colour, std::string* error);

}  // namespace saccade
