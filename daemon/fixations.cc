// `saccade log-fixations` (live, from LCM) and `saccade fixations LOG` (from an lcm-logger
// file): the attention log as CSV or JSON lines.
#include "daemon/args.h"
#include "daemon/commands.h"
#include "daemon/signals.h"
#include "io/bus.h"
#include "io/fixation_log.h"

#include <atomic>
#include <fstream>
#include <ostream>

namespace saccade {
namespace {

const std::string kDefaultUrl = BusOptions{}.url;

// Opens --out (or stdout for "-") with the format its name asks for.
bool OpenOutput(const Args& args, std::ostream& out, std::ofstream* file, std::ostream** stream,
                FixationWriter::Format* format, std::string* error) {
  const std::string path = args.Get("out");
  if (!FixationWriter::FormatOf(path == "-" ? "-.csv" : path, format, error)) return false;
  if (path == "-") {
    *stream = &out;
    return true;
  }
  file->open(path);
  if (!*file) {
    *error = "'" + path + "': cannot write it";
    return false;
  }
  *stream = file;
  return true;
}

}  // namespace

int RunLogFixations(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args;
  std::string error;
  if (!args.Parse(argv, {"channel", "out", "lcm-url", "count"}, {}, &error))
    return Usage(err, "log-fixations", error);
  if (!args.Has("out")) return Usage(err, "log-fixations", "--out FILE.csv|FILE.jsonl is required");
  std::int64_t count = 0;
  if (args.Has("count")) {
    const auto n = Args::ParsePositiveInt(args.Get("count"));
    if (!n) return Usage(err, "log-fixations", "--count must be a positive integer");
    count = *n;
  }
  std::ofstream file;
  std::ostream* stream = nullptr;
  FixationWriter::Format format;
  if (!OpenOutput(args, out, &file, &stream, &format, &error)) {
    err << "saccade log-fixations: " << error << "\n";
    return kExitFailure;
  }
  std::atomic<bool> stop{false};
  SignalWaiter signals([&](int) { stop = true; });  // SIGINT/SIGTERM end the log cleanly
  FixationWriter writer(*stream, format);
  FixationLogStats stats;
  if (!ListenFixations(args.Get("lcm-url", kDefaultUrl),
                       args.Get("channel", FixationChannel("SACCADE")), &writer, count, stop,
                       &stats, &error)) {
    err << "saccade log-fixations: " << error << "\n";
    return kExitFailure;
  }
  err << "saccade log-fixations: " << stats.written << " fixation(s) written";
  if (stats.skipped > 0) err << ", " << stats.skipped << " malformed message(s) skipped";
  err << "\n";
  return kExitOk;
}

int RunFixations(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  if (argv.empty() || argv[0].rfind("--", 0) == 0)
    return Usage(err, "fixations", "the first argument must be an lcm-logger log file");
  const std::string log = argv[0];
  Args args;
  std::string error;
  if (!args.Parse({argv.begin() + 1, argv.end()}, {"channel", "out"}, {}, &error))
    return Usage(err, "fixations", error);
  if (!args.Has("out")) return Usage(err, "fixations", "--out FILE.csv|FILE.jsonl is required");
  std::ofstream file;
  std::ostream* stream = nullptr;
  FixationWriter::Format format;
  if (!OpenOutput(args, out, &file, &stream, &format, &error)) {
    err << "saccade fixations: " << error << "\n";
    return kExitFailure;
  }
  FixationWriter writer(*stream, format);
  FixationLogStats stats;
  if (!ConvertFixationLog(log, args.Get("channel", FixationChannel("SACCADE")), &writer, &stats,
                          &error)) {
    err << "saccade fixations: " << error << "\n";
    return kExitFailure;
  }
  if (stats.skipped > 0)
    err << "saccade fixations: " << stats.skipped << " malformed message(s) skipped\n";
  return kExitOk;
}

}  // namespace saccade
