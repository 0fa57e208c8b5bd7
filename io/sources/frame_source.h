// Where frames come from: OpenNI2 devices and .oni recordings, PCD and depth-image sequences,
// and the synthetic Kinect, behind one interface made from a spec string.
#pragma once

#include "core/frame.h"
#include "io/base/clock.h"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace saccade {

/// What a source is doing, for the daemon's status.
struct SourceStats {
  std::uint64_t produced = 0;  // frames the source made
  std::uint64_t dropped = 0;   // live frames overwritten before the consumer took them
  std::uint64_t skipped = 0;   // frames that could not be read (a corrupt file), skipped
  std::uint64_t reconnects = 0;
  std::uint64_t unpaired = 0;  // depth frames that found no colour frame in time (cameras)
  std::string state;           // "streaming", "ended", "reconnecting: why", ...
};

class FrameSource {
 public:
  enum class Status { kFrame, kEnd, kError };
  virtual ~FrameSource() = default;
  /// Blocks until the next frame, the end of a finite source, or an error the source cannot
  /// recover from (`error` says what). After Stop(), returns kEnd promptly.
  virtual Status Next(Frame* frame, std::string* error) = 0;
  /// Wakes a blocked Next(); safe from any thread (a signal handler's thread, for instance).
  virtual void Stop() = 0;
  virtual SourceStats Stats() const = 0;
  /// True when frames arrive at the sensor's pace whether or not anyone reads them.
  virtual bool Live() const = 0;
  virtual std::string Describe() const = 0;
};

/// How a spec is read. Options come after '?' as key=value pairs joined by '&':
///   openni2://             the first OpenNI2 device (openni2://#N: the N-th, 0-based;
///                          openni2://URI or openni2://SERIAL: that device)
///   freenect://            a Kinect v1 through libfreenect (freenect://N: the N-th, 0-based;
///                          freenect://SERIAL: that one); calibration=FILE, raw=0|1 (see
///                          io/sources/freenect_source.h); under fakenect, its dump replayed
///   PATH.oni               OpenNI2 playback; mode=realtime|fast|step (default fast), loop=0|1
///   pcd:DIR                PCD files in name order; rate=HZ (0: as fast as read), loop=0|1
///   depth:DIR              16-bit PNG/TIFF depth in millimetres (names containing "depth"),
///                          RGB optional (the same name with "rgb"), DIR/intrinsics.yaml or
///                          intrinsics=FILE; rate=HZ, loop=0|1
///   synthetic:NAME         a preset (see ScenarioPresetNames) or a scenario YAML file;
///                          frames=N, seed=S, rate=HZ (0: as fast as rendered), loop=0|1
///   capture:FILE.yaml      a real labelled capture seen again from a moving virtual camera,
///                          one object moving (core/sim/rerender.h); data=DIR (where the
///                          capture is, default ../shared/data), frames=N, rate=HZ, loop=0|1
/// A source with rate > 0 is live: it runs at that rate on its own thread into a latest-frame
/// mailbox and counts what its consumer did not take in time. nullptr with one line in
/// `error` when the spec is malformed or the source cannot be opened. A live camera that is not
/// there yet is waited for up to `wait_at_start_s` (its Stats().state says so) instead.
std::unique_ptr<FrameSource> OpenSource(const std::string& spec, std::string* error,
                                        double wait_at_start_s = 0);

/// A spec split into its kind, its target and its options.
struct SourceSpec {
  std::string kind;    // "openni2", "freenect", "oni", "pcd", "depth", "synthetic", "capture"
  std::string target;  // device, path or scenario name
  std::map<std::string, std::string> options;
};
std::optional<SourceSpec> ParseSourceSpec(const std::string& spec, std::string* error);

/// capture:FILE.yaml[?data=DIR&object=K]: the labelled object of a capture sequence's capture
/// (or K, one of its others), in the capture's frame (what `saccade segment` cuts from it; the
/// sequence's truth X_CO places it).
std::optional<Cloud> LoadCaptureModel(const std::string& spec, std::string* error);

}  // namespace saccade
