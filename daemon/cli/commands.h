// The `saccade` user command's subcommands. Each returns the process exit code
// (daemon/exit_codes.h).
#pragma once

#include "daemon/exit_codes.h"

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// Prints "saccade COMMAND: MESSAGE" and returns kExitUsage.
int Usage(std::ostream& err, const std::string& command, const std::string& message);
/// An exit code when `path` cannot take a PNG (not .png, a folder, no such folder), said in one
/// line; nothing when it can. Checked before the work, not after it.
std::optional<int> CheckPngPath(const std::string& path, const std::string& command,
                                std::ostream& err);

int RunRecognize(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunBench(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunRecord(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunLogFixations(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunDetections(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunFixations(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
/// saccade mcap: an lcm-logger log of saccaded as an MCAP file of ROS 2 messages.
int RunMcap(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
/// saccade view: the live web viewer.
int RunView(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunModel(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunSegment(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
/// saccade labels: each label of a labelled scene, its points, centroid and extent.
int RunLabels(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
/// saccade keygen: the key that signs commands; saccade command: one command to saccaded.
int RunKeygen(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunSendCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunEval(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunBenchTrack(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunDemo(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace saccade
