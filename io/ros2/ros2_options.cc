#include "core/fail.h"
#include "io/ros2/ros2.h"

#include <cctype>

namespace saccade {

bool Ros2Options::IsValid(std::string* error) const {
  // A ROS 2 name: '/' and then tokens of letters, digits and '_' joined by '/'.
  bool ok = topic_prefix.size() >= 2 && topic_prefix.size() <= 200 && topic_prefix[0] == '/' &&
            topic_prefix.back() != '/';
  for (std::size_t i = 1; ok && i < topic_prefix.size(); ++i) {
    const char c = topic_prefix[i];
    ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
         (c == '/' && topic_prefix[i - 1] != '/');
  }
  if (!ok)
    return Fail(error,
                "topic_prefix must be a ROS 2 name: '/' then letters, digits, '_' and single "
                "'/' (e.g. /saccade), at most 200 characters");
  if (camera_frame_id.empty() || camera_frame_id.size() > 200)
    return Fail(error, "camera_frame_id must be 1 to 200 characters");
  if (depth < 1 || depth > 1000) return Fail(error, "depth must be 1 to 1000");
  return true;
}

bool McapLogOptions::IsValid(std::string* error) const {
  if (!(mcap_max_mb >= 0.01 && mcap_max_mb <= 1e6))
    return Fail(error, "mcap_max_mb must be 0.01 to 1000000");
  if (!mcap.empty() && mcap.back() == '/')
    return Fail(error, "mcap must name a file, not a folder");
  return true;
}

}  // namespace saccade
