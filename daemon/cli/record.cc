// saccade record: capture from any source into a folder (PCD or depth images, with ground
// truth), an .oni recording, or a fakenect dump (a Kinect v1's raw frames).
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/cli/progress.h"
#include "daemon/signals.h"
#include "io/formats/fakenect_dump.h"
#include "io/formats/frame_writer.h"
#include "io/sources/frame_source.h"
#include "io/sources/openni2_source.h"

#include <signal.h>

#include <filesystem>
#include <mutex>
#include <ostream>

namespace saccade {

int RunRecord(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade record",
            "Captures frames from a source into a folder, with ground truth when the source "
            "has it; Ctrl-C ends it and keeps what was captured.");
  args.Value("source", "SPEC",
             "where frames come from (required): "
             "openni2://[#N|URI|SERIAL][?registration=auto|device|saccade|none&calibration=F], "
             "freenect://[N|SERIAL][?calibration=F&raw=1], "
             "PATH.oni[?mode=realtime|fast|step&loop=1], pcd:DIR[?rate=HZ&loop=1], "
             "depth:DIR[?intrinsics=FILE&rate=HZ&loop=1], "
             "synthetic:NAME[?frames=N&seed=S&rate=HZ&loop=1] (NAME: a preset or a YAML "
             "file); docs/SOURCES.md")
      .Value("out", "DIR", "the folder to write (required)")
      .Value("frames", "N", "stop after N frames (default: the source's end or Ctrl-C)")
      .Value("format", "FORMAT",
             "pcd (clouds), depth (16-bit PNG in millimetres), oni "
             "(OpenNI2) or fakenect (a Kinect v1 dump) (default: pcd)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  if (!args.Has("source") || !args.Has("out"))
    return Usage(err, "record", "--source and --out are required");
  std::optional<int> frames;
  if (args.Has("frames")) {
    frames = Args::ParsePositiveInt(args.Get("frames"));
    if (!frames) return Usage(err, "record", "--frames must be a whole number >= 1");
  }
  const std::string format = args.Get("format", "pcd");
  if (format != "pcd" && format != "depth" && format != "oni" && format != "fakenect")
    return Usage(err, "record", "--format must be pcd, depth, oni or fakenect");
  const std::string dir = args.Get("out");

  // Ctrl-C or SIGTERM ends a recording cleanly: what was captured is kept.
  FrameSource* running = nullptr;
  std::mutex running_mutex;
  SignalWaiter signals([&](int signo) {
    if (signo == SIGHUP) return;
    std::lock_guard<std::mutex> lock(running_mutex);
    if (running) running->Stop();
  });
  auto source = OpenSource(args.Get("source"), &error);
  if (!source) {
    err << "saccade record: " << error << "\n";
    return kExitFailure;
  }
  {
    std::lock_guard<std::mutex> lock(running_mutex);
    running = source.get();
  }
  std::unique_ptr<FrameWriter> writer;
  std::unique_ptr<FakenectWriter> dump;
  // The output is made when the first frame has come, so that a source that fails before it
  // writes nothing (or when the source ends without one: an empty recording). An .oni
  // recording starts with the device instead.
  auto open_output = [&](std::string* why) -> bool {
    if (format == "fakenect") {
      dump = FakenectWriter::Open(dir, NominalKinectCalibration(), why);
      return dump != nullptr;
    }
    writer = FrameWriter::Open(
        dir, format == "pcd" ? FrameWriter::Format::kPcd : FrameWriter::Format::kDepth, why);
    return writer != nullptr;
  };
  if (format == "oni") {
    auto* openni = dynamic_cast<OpenNI2Source*>(source.get());
    if (!openni) {
      err << "saccade record: --format oni needs an OpenNI2 source (openni2:// or .oni); "
             "record depth images and play them through the virtual device instead "
             "(docs/SOURCES.md)\n";
      return kExitUsage;
    }
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (!openni->StartRecording((std::filesystem::path(dir) / "recording.oni").string(), &error)) {
      err << "saccade record: " << error << "\n";
      return kExitFailure;
    }
  }
  int taken = 0;
  Frame frame;
  int code = kExitOk;
  ProgressLine progress(err, ProgressLine::StderrIsATerminal());  // on a terminal only
  while (!frames || taken < *frames) {
    progress.Show("saccade record: frames", std::size_t(taken), frames ? std::size_t(*frames) : 0);
    const auto status = source->Next(&frame, &error);
    if (status == FrameSource::Status::kEnd) break;
    if (status == FrameSource::Status::kError ||
        (format != "oni" && !writer && !dump && !open_output(&error)) ||
        (writer && !writer->Write(frame, &error)) || (dump && !dump->Write(frame, &error))) {
      progress.Clear();
      err << "saccade record: " << error << "\n";
      code = kExitFailure;
      break;
    }
    ++taken;
  }
  if (code == kExitOk && format != "oni" && !writer && !dump && !open_output(&error)) {
    err << "saccade record: " << error << "\n";
    code = kExitFailure;
  }
  progress.Clear();
  if (auto* openni = dynamic_cast<OpenNI2Source*>(source.get())) openni->StopRecording();
  {
    std::lock_guard<std::mutex> lock(running_mutex);
    running = nullptr;
  }
  if (code != kExitOk && taken == 0) return code;  // the line said it; nothing was recorded
  const SourceStats stats = source->Stats();
  out << "recorded " << taken << " frame(s) from " << source->Describe() << " to " << dir << " ("
      << format << "), " << stats.dropped << " dropped";
  if (stats.unpaired > 0) out << ", " << stats.unpaired << " without their colour frame";
  if (stats.skipped > 0) out << ", " << stats.skipped << " unusable skipped";
  out << "\n";
  return code;
}

}  // namespace saccade
