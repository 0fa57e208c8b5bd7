// The build without Cyclone DDS (cyclonedds-dev was not found at configure time).
#include "core/fail.h"
#include "io/ros2/mcap_log.h"
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

bool ConvertLcmLogToMcap(const std::string&, const std::string&, const std::string&,
                         const Ros2Options&, McapCounts*, std::string* error) {
  return Fail(error,
              "this saccade was built without Cyclone DDS, which MCAP's ROS 2 messages are "
              "serialized with (install cyclonedds-dev and cyclonedds-tools, then rebuild)");
}

std::unique_ptr<MessageMirror> OpenMcapMirror(const std::string&, std::uint64_t, const Ros2Options&,
                                              std::string* error) {
  Fail(error,
       "log.mcap: this saccaded was built without Cyclone DDS (install cyclonedds-dev "
       "and cyclonedds-tools, then rebuild)");
  return nullptr;
}

}  // namespace saccade
