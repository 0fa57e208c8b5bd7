// The build without Cyclone DDS (cyclonedds-dev was not found at configure time).
#include "core/fail.h"
#include "io/ros2/ros2.h"

namespace saccade {

bool Ros2Built() { return false; }

std::unique_ptr<MessageMirror> OpenRos2Mirror(const Ros2Options&, const RobotFrameOptions&,
                                              std::string* error) {
  Fail(error,
       "ros2: this saccaded was built without Cyclone DDS (install cyclonedds-dev and "
       "cyclonedds-tools, then rebuild)");
  return nullptr;
}

}  // namespace saccade
