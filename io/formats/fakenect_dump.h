// libfreenect's "fakenect" dumps: the folder fakenect-record writes and Debian's fakenect (a
// libfreenect that replays a dump, package libfreenect-bin) plays back. INDEX.txt lists the
// files in time order, one a line: d-SECONDS-TIMESTAMP.pgm (depth: a one-line "P5 640 480
// 65535" header, then 640 x 480 raw 11-bit disparities as host-order uint16, 2047 for no
// return), r-SECONDS-TIMESTAMP.ppm (colour: "P6 640 480 255", then 640 x 480 RGB) and
// a-SECONDS-TIMESTAMP.dump (the accelerometer: a freenect_raw_tilt_state). SECONDS is the host's
// clock when recorded, which paces the replay; TIMESTAMP is the Kinect's 60 MHz frame clock (32
// bits, wrapping).
//
// fakenect replays what a Kinect sends in its raw modes only (FREENECT_DEPTH_11BIT and
// FREENECT_VIDEO_RGB at 640x480), and exits the process on a file it cannot open, so a dump is
// checked whole before libfreenect sees it.
#pragma once

#include "io/formats/output_file.h"

#include "core/frame.h"
#include "core/registration.h"

#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

namespace saccade {

constexpr int kKinectWidth = 640, kKinectHeight = 480;
constexpr double kKinectClockHz = 60e6;  // the frame timestamps' clock

/// Checks a dump before replay: INDEX.txt there, every line a d-/r-/a- file name that exists,
/// depth and colour files with fakenect's one-line header and exactly their pixels' bytes.
/// `depth_frames` receives the number of depth frames. One line naming the file otherwise.
bool CheckFakenectDump(const std::string& dir, int* depth_frames, std::string* error);

/// Writes frames as a dump a Kinect v1 would have made: each frame's depth moved from its
/// camera into the depth camera of `calibration` and turned into raw disparity, its colour seen
/// by the colour camera. A frame replayed through freenect:// with the same calibration comes
/// back in the colour camera's frame: the frame's own when its intrinsics are the colour
/// camera's (the synthetic Kinect's are).
class FakenectWriter {
 public:
  static std::unique_ptr<FakenectWriter> Open(const std::string& dir,
                                              const ColourCalibration& calibration,
                                              std::string* error);
  /// False with one line naming the file when it cannot be written, or when the frame is not
  /// captured after the one before it (the times name the files).
  bool Write(const Frame& frame, std::string* error);

 private:
  FakenectWriter() = default;
  std::string dir_;
  ColourCalibration calibration_;
  RecordFile index_;                        // INDEX.txt, a whole line per file
  std::optional<std::int64_t> last_utime_;  // of the last frame written
};

}  // namespace saccade
