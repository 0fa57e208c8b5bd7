// saccade mcap: an lcm-logger log of saccaded as an MCAP file of ROS 2 messages (docs/ROS2.md).
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "io/lcm/bus.h"
#include "io/ros2/mcap_log.h"
#include "io/ros2/ros2.h"

#include <ostream>

namespace saccade {

int RunMcap(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade mcap",
            "Turns an lcm-logger log of saccaded into an MCAP file of ROS 2 messages (profile "
            "ros2, CDR, ros2msg schemas), as saccaded --ros2 publishes them: PREFIX/detections "
            "(vision_msgs/Detection3DArray), PREFIX/fixation (geometry_msgs/PointStamped), "
            "/diagnostics once a second, and the previews when the log has them: their points as "
            "PREFIX/foveated_cloud (sensor_msgs/PointCloud2) and their JPEGs as "
            "PREFIX/preview/compressed (sensor_msgs/CompressedImage). "
            "Foxglove opens it; ros2 bag play plays it (docs/ROS2.md).");
  args.Positional("LOG.lcmlog", "the lcm-logger log (required)")
      .Value("out", "OUT.mcap", "the MCAP file to write (required; -o is the same)")
      .Value("channel-prefix", "PREFIX", "saccaded's LCM channels' prefix (default: SACCADE)")
      .Value("topic-prefix", "/NAME", "the ROS 2 topics' prefix (default: /saccade)")
      .Value("camera-frame-id", "NAME",
             "header.frame_id of what is in the camera frame (default: camera)");
  std::vector<std::string> flags = argv;
  for (std::string& a : flags)
    if (a == "-o") a = "--out";
  if (auto code = args.Parse(flags, out, err)) return *code;
  if (!args.Has("LOG.lcmlog"))
    return Usage(err, "mcap", "the first argument must be an lcm-logger log file");
  if (!args.Has("out")) return Usage(err, "mcap", "--out OUT.mcap is required");
  Ros2Options options;
  options.topic_prefix = args.Get("topic-prefix", options.topic_prefix);
  options.camera_frame_id = args.Get("camera-frame-id", options.camera_frame_id);
  std::string error;
  if (!options.IsValid(&error)) return Usage(err, "mcap", error);
  const std::string prefix = args.Get("channel-prefix", "SACCADE");
  McapCounts counts;
  if (!ConvertLcmLogToMcap(args.Get("LOG.lcmlog"), prefix, args.Get("out"), options, &counts,
                           &error)) {
    err << "saccade mcap: " << error << "\n";
    return kExitFailure;
  }
  out << "wrote " << args.Get("out") << ": " << counts.detections << " detections, "
      << counts.fixations << " fixations, " << counts.diagnostics << " diagnostics, "
      << counts.previews << " previews (cloud and image)";
  if (counts.skipped > 0) out << "; " << counts.skipped << " malformed message(s) skipped";
  out << "\n";
  return kExitOk;
}

}  // namespace saccade
