// `saccade log-fixations` (live, from LCM), `saccade fixations LOG` and `saccade detections
// LOG` (from an lcm-logger file): what saccaded published, as CSV or JSON lines.
#include "core/fail.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/signals.h"
#include "io/formats/output_file.h"
#include "io/lcm/bus.h"
#include "io/lcm/detections_log.h"
#include "io/lcm/fixation_log.h"
#include "io/lcm/lcm_open.h"

#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <cstdio>
#include <functional>
#include <memory>
#include <ostream>
#include <sstream>

namespace saccade {
namespace {

const std::string kDefaultUrl = BusOptions{}.url;

constexpr const char* kOutRequired = "--out FILE.csv|FILE.jsonl is required";

// Where a fixation log goes: --out (or stdout for "-"), in the format its name asks for. Each
// fixation is formatted into `pending`, then appended to the file whole (or not at all).
struct Output {
  RecordFile file;
  std::ostringstream pending;
  std::unique_ptr<FixationWriter> writer;
};

// The format --out asks for ("-": CSV on stdout); false with `error` for an unknown one.
bool OutputFormat(const Args& args, FixationWriter::Format* format, std::string* error) {
  const std::string path = args.Get("out");
  return FixationWriter::FormatOf(path == "-" ? "-.csv" : path, format, error);
}

// Opens --out; false with `error` when its format is unknown or it cannot be written.
bool OpenOutput(const Args& args, std::ostream& out, Output* output, std::string* error) {
  const std::string path = args.Get("out");
  FixationWriter::Format format;
  if (!OutputFormat(args, &format, error)) return false;
  output->writer = std::make_unique<FixationWriter>(path == "-" ? out : output->pending, format);
  if (path == "-") return true;
  // The header goes in at once: a log of no fixation is still a table.
  if (!output->file.Open(path, error)) return false;
  if (!output->file.Append(output->pending.str(), error)) {
    output->file.Close(nullptr);
    std::remove(path.c_str());  // not even a header fitted: no file
    return false;
  }
  output->pending.str("");
  return true;
}

}  // namespace

int RunLogFixations(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade log-fixations",
            "Subscribes to saccaded's fixations and logs them until SIGINT (or --count of "
            "them).");
  args.Value("out", "FILE.csv|FILE.jsonl",
             "where to write, in the format its name says; - "
             "for CSV on stdout (required)")
      .Value("channel", "NAME", "the fixation channel (default: SACCADE_FIXATION)")
      .Value("lcm-url", "URL", "the LCM network (default: " + kDefaultUrl + ")")
      .Value("count", "N", "stop after N fixations");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  if (!args.Has("out")) return Usage(err, "log-fixations", kOutRequired);
  FixationWriter::Format format;
  if (!OutputFormat(args, &format, &error)) return Usage(err, "log-fixations", error);
  std::int64_t count = 0;
  if (args.Has("count")) {
    const auto n = Args::ParsePositiveInt(args.Get("count"));
    if (!n) return Usage(err, "log-fixations", "--count must be a positive integer");
    count = *n;
  }
  // LCM first: a network that cannot be joined leaves no output file behind.
  std::unique_ptr<lcm::LCM> lcm = OpenLcm(args.Get("lcm-url", BusOptions{}.url), &error);
  Output output;
  if (!lcm || !OpenOutput(args, out, &output, &error)) {
    err << "saccade log-fixations: " << error << "\n";
    return kExitFailure;
  }
  std::atomic<bool> stop{false};
  SignalWaiter signals([&](int) { stop = true; });  // SIGINT/SIGTERM end the log cleanly
  LcmLogStats stats;
  // Each fixation goes to the file as it comes, whole: a full disk ends the log with the
  // fixations before it kept, and the file ends on a whole line.
  std::string failure;
  const auto flushed = [&] {
    if (!output.file.is_open()) return static_cast<bool>(out.flush());
    const bool ok = output.file.Append(output.pending.str(), &failure);
    output.pending.str("");
    return ok;
  };
  ListenFixations(lcm.get(), args.Get("channel", FixationChannel("SACCADE")), output.writer.get(),
                  count, stop, &stats, flushed);
  if (failure.empty()) output.file.Close(&failure);
  if (!failure.empty()) {
    err << "saccade log-fixations: " << failure << "; the " << stats.written
        << " fixation(s) before it are kept whole\n";
    return kExitFailure;
  }
  err << "saccade log-fixations: " << stats.written << " fixation(s) written";
  if (stats.skipped > 0) err << ", " << stats.skipped << " malformed message(s) skipped";
  err << "\n";
  return kExitOk;
}

namespace {

// What a log conversion needs of its message type: the converter writing `log`'s messages on
// `channel` to `out` in `format`.
using Converter =
    std::function<bool(const std::string& log, const std::string& channel, std::ostream& out,
                       TableFormat format, LcmLogStats* stats, std::string* error)>;

// `saccade fixations` and `saccade detections`: LOG.lcmlog --out FILE [--channel NAME]. The log
// is checked before the output is opened (a log that is not one writes nothing), and a log in
// which nothing decodes is an error that leaves no file of a header alone.
int RunLogConversion(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err,
                     const std::string& command, const std::string& type, const std::string& about,
                     const std::string& channel, const Converter& convert) {
  Args args("saccade " + command, about);
  args.Positional("LOG.lcmlog", "the lcm-logger log (required)")
      .Value("out", "FILE.csv|FILE.jsonl",
             "where to write, in the format its name says; - for CSV on stdout (required)")
      .Value("channel", "NAME", "the channel (default: " + channel + ")");
  if (auto code = args.Parse(argv, out, err)) return *code;
  if (!args.Has("LOG.lcmlog"))
    return Usage(err, command, "the first argument must be an lcm-logger log file");
  if (!args.Has("out")) return Usage(err, command, kOutRequired);
  const std::string log = args.Get("LOG.lcmlog"), path = args.Get("out");
  std::string error;
  TableFormat format;
  if (!TableFormatOf(path == "-" ? "-.csv" : path, &format, &error))
    return Usage(err, command, error);
  const auto fail = [&](const std::string& message) {
    err << "saccade " << command << ": " << message << "\n";
    return kExitFailure;
  };
  if (!CheckLcmLog(log, &error)) return fail(error);
  // Converted in memory, then written whole (beside its place and renamed) or not at all.
  std::ostringstream table;
  LcmLogStats stats;
  if (!convert(log, args.Get("channel", channel), path == "-" ? out : table, format, &stats,
               &error))
    return fail(error);
  if (stats.written == 0 && stats.skipped > 0) {
    return fail(log + ": none of the " + std::to_string(stats.skipped) +
                " message(s) on the channel decode as a " + type +
                " (a log of an older saccaded, whose types had another fingerprint, or of "
                "another type)");
  }
  if (path != "-" && !WriteBytes(path, table.str(), &error)) return fail(error);
  if (stats.skipped > 0)
    err << "saccade " << command << ": " << stats.skipped << " malformed message(s) skipped\n";
  return kExitOk;
}

}  // namespace

int RunFixations(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  return RunLogConversion(
      argv, out, err, "fixations", "fixation_t",
      "Converts the fixations in an lcm-logger log to CSV or JSON lines, as log-fixations "
      "writes them.",
      FixationChannel("SACCADE"),
      [](const std::string& log, const std::string& channel, std::ostream& to, TableFormat format,
         LcmLogStats* stats, std::string* error) {
        FixationWriter writer(to, format);
        return ConvertFixationLog(log, channel, &writer, stats, error);
      });
}

int RunDetections(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  return RunLogConversion(
      argv, out, err, "detections", "detections_t",
      "Converts the detections in an lcm-logger log to CSV (one row per instance: where it is, "
      "its confidence and track) or JSON lines (one line per frame).",
      DetectionsChannel("SACCADE"),
      [](const std::string& log, const std::string& channel, std::ostream& to, TableFormat format,
         LcmLogStats* stats, std::string* error) {
        DetectionWriter writer(to, format);
        return ConvertDetectionLog(log, channel, &writer, stats, error);
      });
}

}  // namespace saccade
