// saccade: the user's command line, one subcommand per task (saccade --help lists them).
#include "daemon/args.h"
#include "daemon/cli/commands.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace {

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const std::vector<std::string>&, std::ostream&, std::ostream&);
};

constexpr Command kCommands[] = {
    {"recognize", "find the model in one scene; print each instance's pose and votes",
     saccade::RunRecognize},
    {"bench", "time plain against foveated recognition on one frame", saccade::RunBench},
    {"bench-track", "the tracker on a sequence with truth at the sensor's rate",
     saccade::RunBenchTrack},
    {"record", "capture frames from a camera, a recording or a synthetic scene",
     saccade::RunRecord},
    {"log-fixations", "subscribe to saccaded's fixations and log them (CSV, JSON lines)",
     saccade::RunLogFixations},
    {"fixations", "convert the fixations in an lcm-logger log (CSV, JSON lines)",
     saccade::RunFixations},
    {"detections", "convert the detections in an lcm-logger log (CSV, JSON lines)",
     saccade::RunDetections},
    {"mcap", "turn an lcm-logger log into an MCAP file of ROS 2 messages (Foxglove, rosbag2)",
     saccade::RunMcap},
    {"command", "send saccaded a command (signed when a key is at hand)", saccade::RunSendCommand},
    {"keygen", "make the key that signs saccaded's commands", saccade::RunKeygen},
    {"view", "serve a live web page of what saccaded sees (camera, 3D, strips)", saccade::RunView},
    {"segment", "cut an object out of a capture as a model", saccade::RunSegment},
    {"labels", "each label of a labelled scene: points, centroid, extent", saccade::RunLabels},
    {"model", "make a model from a mesh (.obj, .ply, .stl)", saccade::RunModel},
    {"eval", "recognition configurations over frames or cases with ground truth", saccade::RunEval},
    {"demo", "find a target in a synthetic Kinect scene", saccade::RunDemo},
};

void PrintUsage(std::ostream& out) {
  out << "usage: saccade <command> [flags]    (saccade <command> --help lists its flags)\n\n"
         "commands:\n";
  for (const Command& c : kCommands) {
    const std::string name = c.name;
    out << "  " << name << std::string(name.size() < 15 ? 15 - name.size() : 1, ' ') << c.summary
        << "\n";
  }
  out << "\n  --version      print the version and the libraries' versions\n"
         "\nexit codes: 0 ok, 1 input could not be processed, 2 bad usage\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // a closed pipe on stdout fails a write, it does not kill
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    PrintUsage(args.empty() ? std::cerr : std::cout);
    return args.empty() ? saccade::kExitUsage : saccade::kExitOk;
  }
  if (args[0] == "--version") {
    std::cout << saccade::VersionText("saccade") << "\n";
    return saccade::kExitOk;
  }
  if (args[0] == "help" && args.size() == 2) args = {args[1], "--help"};  // saccade help eval
  if (args[0] == "help" && args.size() == 1) {
    PrintUsage(std::cout);
    return saccade::kExitOk;
  }
  std::vector<std::string> names;
  for (const Command& c : kCommands) {
    names.push_back(c.name);
    if (args[0] != c.name) continue;
    const int code = c.run({args.begin() + 1, args.end()}, std::cout, std::cerr);
    // What went to stdout must have reached it: `saccade labels --json > /full/disk.json` is a
    // failure, not a success with nothing written.
    errno = 0;
    if (!std::cout.flush() || std::fflush(stdout) != 0) {
      std::cerr << "saccade " << c.name << ": cannot write standard output ("
                << (errno != 0 ? std::strerror(errno) : "write failed") << ")\n";
      return code == saccade::kExitOk ? saccade::kExitFailure : code;
    }
    return code;
  }
  const std::string near = saccade::Args::Nearest(args[0], names);
  std::cerr << "saccade: unknown command '" << args[0] << "'"
            << (near.empty() ? "" : " (did you mean " + near + "?)") << " (see saccade --help)\n";
  return saccade::kExitUsage;
}
