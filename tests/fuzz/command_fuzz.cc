// libFuzzer target: the decoders of what arrives over LCM, on arbitrary bytes: the command
// decoder (DecodeCommand in io/lcm/bus.h, what the command channel delivers to the daemon), and
// the fixation and detections decoders the log converters use (io/lcm/fixation_log.h,
// io/lcm/detections_log.h), and the viewer's state fed the bytes on each of its channels
// (io/viewer/viewer.h: detections, fixation, status and preview, io/lcm/preview.h). Each must
// return a message or refuse, never crash.
//
// Then what the daemon does with a command that decoded (Tracker::Impl::OnCommand in
// daemon/tracker.cc, and ApplyFixationCommand in daemon/attention_command.cc, which the
// daemon's attention stage calls: the stages themselves are too heavy to build into a target): a
// SWITCH_MODEL's path goes through CommandModelAllowed against a model folder that holds a
// model, a pipe, a link out and a folder, and what it allows must be one of the folder's
// regular files, found by walking the folder without following links and compared by device
// and inode (not through realpath, which CommandModelAllowed uses); a SET_FOVEA or RESET
// resets the attention loop, and the fixation it gives places the fovea's boxes and foveates a
// small cloud, as the next frame would. DecodeCommand has already bounded the fovea, so that
// part's checks are invariants; what it looks for is the sanitizers' reports. Describing an
// allowed model is the PCD loader's (the `pcd` target) and is not done here.
#include "attention/attention.h"
#include "core/foveation.h"
#include "daemon/attention_command.h"
#include "io/lcm/bus.h"
#include "io/lcm/command_key.h"
#include "io/lcm/detections_log.h"
#include "io/lcm/fixation_log.h"
#include "io/viewer/viewer.h"

#include <sys/stat.h>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The seed corpus's SWITCH_MODEL messages name these paths.
const std::string kModelRoot = "/tmp/saccade-fuzz-models";

// The model folder: models/mug.pcd (allowed), models/pipe.pcd (a FIFO), models/link.pcd (a link
// to secret.pcd, outside), models/sub (a folder). Made once a process.
const std::string& ModelDir() {
  static const std::string dir = [] {
    fs::create_directories(kModelRoot + "/models/sub");
    std::ofstream(kModelRoot + "/models/mug.pcd") << "x";
    std::ofstream(kModelRoot + "/secret.pcd") << "x";
    std::error_code ignored;
    fs::create_symlink(kModelRoot + "/secret.pcd", kModelRoot + "/models/link.pcd", ignored);
    mkfifo((kModelRoot + "/models/pipe.pcd").c_str(), 0600);  // EEXIST from an earlier run
    return kModelRoot + "/models";
  }();
  return dir;
}

// The regular files in the model folder (not links to them), as device and inode: what a
// SWITCH_MODEL may name, by whatever path.
const std::set<std::pair<dev_t, ino_t>>& ModelFiles() {
  static const std::set<std::pair<dev_t, ino_t>> files = [] {
    std::set<std::pair<dev_t, ino_t>> found;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(ModelDir())) {
      struct stat st;
      if (e.symlink_status().type() == fs::file_type::regular && lstat(e.path().c_str(), &st) == 0)
        found.insert({st.st_dev, st.st_ino});
    }
    return found;
  }();
  return files;
}

// A 20 x 20 cm plane of 441 points 1 m in front of the camera: what the next frame foveates.
const saccade::Cloud& NextFrame() {
  static const saccade::Cloud cloud = [] {
    saccade::Cloud c;
    for (int i = -10; i <= 10; ++i)
      for (int j = -10; j <= 10; ++j) {
        saccade::PointT p;
        p.x = 0.01f * i;
        p.y = 0.01f * j;
        p.z = 1.0f;
        c.push_back(p);
      }
    return c;
  }();
  return cloud;
}

void HandleSwitchModel(const std::string& spec) {
  std::string why;
  const bool allowed = saccade::CommandModelAllowed(spec, {ModelDir()}, &why);
  if (!allowed && (why.empty() || why.find('\n') != std::string::npos)) __builtin_trap();
  if (!allowed || spec == "synthetic:target") return;
  struct stat st;
  if (stat(spec.c_str(), &st) != 0 || ModelFiles().count({st.st_dev, st.st_ino}) == 0)
    __builtin_trap();
}

void HandleFovea(const saccade::Command& command) {
  const saccade::AttentionOptions options;
  const Eigen::Vector3f initial(0, 0, 1);
  saccade::Attention attention(options, initial);
  attention.Update(0, 0.0, {}, {});
  saccade::ApplyFixationCommand(command, initial, &attention);
  const saccade::Fixation& f = attention.current();
  if (!f.fovea_m.allFinite() || !(f.growth_m >= options.growth_min_m) ||
      !(f.growth_m <= options.growth_max_m))
    __builtin_trap();
  saccade::FoveaOptions fovea;
  fovea.growth_m = Eigen::Vector3f::Constant(f.growth_m);
  const auto bounds = saccade::BoundingBox(NextFrame());
  const saccade::FoveatedCloud foveated = saccade::Foveate(
      NextFrame(), fovea, saccade::ComputeFoveaGeometry(fovea, *bounds, f.fovea_m));
  if (foveated.cloud.size() > NextFrame().size()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The gate of signed commands sees every input first, as the bus does with a key: a verdict
  // of one line either way (a fixed key and clock; seed signed-pause.bin passes it).
  saccade::Digest key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(i + 1);
  saccade::CommandGate gate(key, 30.0, [] { return std::int64_t{1'800'000'000'000'000}; });
  std::string refused;
  if (!gate.Admit(data, size, &refused) &&
      (refused.empty() || refused.find('\n') != std::string::npos))
    __builtin_trap();
  std::string why;
  const auto command = saccade::DecodeCommand(data, size, saccade::BusOptions{},
                                              Eigen::Isometry3f::Identity(), &why);
  if (!command && (why.empty() || why.find('\n') != std::string::npos)) __builtin_trap();
  if (command) {
    switch (command->kind) {
      case saccade::Command::Kind::kSwitchModel:
        HandleSwitchModel(command->model);
        break;
      case saccade::Command::Kind::kSetFovea:
      case saccade::Command::Kind::kReset:
        HandleFovea(*command);
        break;
      case saccade::Command::Kind::kPause:
      case saccade::Command::Kind::kResume:
        break;  // a flag under the tracker's lock: nothing of the message's is used
    }
  }
  // The same bytes as the other messages: what decodes is also written, as the converters do.
  std::ostringstream out;
  saccade::LoggedFixation fixation;
  if (saccade::DecodeFixation(data, size, &fixation))
    saccade::FixationWriter(out, saccade::TableFormat::kCsv).Write(fixation);
  saccade::LoggedDetections detections;
  if (saccade::DecodeDetections(data, size, &detections))
    saccade::DetectionWriter(out, saccade::TableFormat::kJsonl).Write(detections);
  // The viewer: every channel it listens to, twice (what it keeps from one message to the
  // next: strips, trail, the drop count), then its state and preview as served. A viewer for
  // each input, so an input found crashing crashes again alone.
  saccade::ViewerState viewer{saccade::ViewerOptions{}};
  for (const double now_s : {1.0, 2.0})
    for (const char* channel :
         {"SACCADE_DETECTIONS", "SACCADE_FIXATION", "SACCADE_STATUS", "SACCADE_PREVIEW"})
      viewer.OnMessage(channel, data, size, now_s);
  if (viewer.StateJson(2.0).empty()) __builtin_trap();
  viewer.PreviewImage(-1);
  viewer.PreviewPoints(-1);
  return 0;
}
