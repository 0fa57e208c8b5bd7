// freenect://[INDEX|SERIAL]: a Microsoft Kinect v1 through Debian's libfreenect.
#pragma once

#include "io/sources/frame_source.h"

#include <memory>
#include <string>

namespace saccade {

struct FreenectOptions {
  /// A colour camera file (io/formats/images.h) for the colour camera's intrinsics and its place
  /// relative to the depth camera; "" keeps NominalKinectCalibration().
  std::string calibration;
  /// Take the raw 11-bit disparity even when the device offers depth registered to colour.
  bool raw = false;
};

/// `device`: "" or an index ("0", the first) or a camera serial number. Frames are depth
/// registered to colour, in metres, in the colour camera's frame, with colour: from the
/// device's own registration (FREENECT_DEPTH_REGISTERED, millimetres) when it offers it, or
/// from its raw disparity (FREENECT_DEPTH_11BIT, which is all fakenect replays) converted and
/// moved into the colour camera by Saccade (core/registration.h). Depth and colour frames are
/// paired by the Kinect's timestamps as OpenNI2's are (io/sources/frame_pairer.h: within half a
/// frame period; a depth frame left without colour is delivered uncoloured and counted). Live: a
/// latest-frame mailbox; when no frame has come for 2 s, or libfreenect fails, the device is closed
/// and reopened with back-off (0.5 s doubling to 8 s); a device not there at start is waited for up
/// to `wait_at_start_s`, as OpenOpenNI2Device does.
///
/// Under fakenect (FAKENECT_PATH set) the dump is checked whole first (CheckFakenectDump), it
/// is played for a reader that takes every frame (none dropped, no stall reconnect), and its
/// end ends the source.
std::unique_ptr<FrameSource> OpenFreenectDevice(const std::string& device,
                                                const FreenectOptions& options,
                                                double wait_at_start_s, std::string* error);

}  // namespace saccade
