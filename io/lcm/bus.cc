#include "io/lcm/bus.h"

#include "core/fail.h"
#include "io/base/clock.h"
#include "io/base/log.h"
#include "io/base/text.h"
#include "io/lcm/lcm_open.h"
#include "io/lcm/preview.h"

#include <poll.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/command_t.hpp>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <thread>

namespace saccade {

std::string DetectionsChannel(const std::string& prefix) { return prefix + "_DETECTIONS"; }
std::string FixationChannel(const std::string& prefix) { return prefix + "_FIXATION"; }
std::string StatusChannel(const std::string& prefix) { return prefix + "_STATUS"; }
std::string CommandChannel(const std::string& prefix) { return prefix + "_COMMAND"; }
std::string PreviewChannel(const std::string& prefix) { return prefix + "_PREVIEW"; }

bool CommandModelAllowed(const std::string& spec, const std::vector<std::string>& dirs,
                         std::string* why) {
  if (spec == "synthetic:target") return true;
  std::string all;
  for (const auto& d : dirs) all += (all.empty() ? "" : ", ") + d;
  const std::string where = " (model folders: " + (all.empty() ? "none" : all) + ")";
  char* real = realpath(spec.c_str(), nullptr);
  if (!real) return Fail(why, "SWITCH_MODEL: no such file '" + spec + "'");
  const std::string path = real;
  std::free(real);
  if (!IsRegularFile(path)) return Fail(why, "SWITCH_MODEL: '" + spec + "' is not a regular file");
  for (const auto& d : dirs) {
    char* dir = realpath(d.c_str(), nullptr);
    if (!dir) continue;
    const std::string prefix = std::string(dir) + (std::string(dir) == "/" ? "" : "/");
    std::free(dir);
    if (path.rfind(prefix, 0) == 0) return true;
  }
  return Fail(why, "SWITCH_MODEL: '" + spec + "' is not under a model folder" + where);
}

namespace {

// command_t's layout: the type's 8-byte hash, utime (8), sequence (8), kind (1), fovea (3 x 8),
// then the model string as a big-endian int32 length (its bytes with the final NUL) and the
// bytes, then the signature (32).
constexpr std::size_t kCommandFixedBytes = 8 + 8 + 8 + 1 + 24;
constexpr std::size_t kSignatureBytes = kCommandSignatureBytes;  // io/lcm/command_key.h
constexpr std::int32_t kMaxModelBytes = 4096;

}  // namespace

std::optional<Command> DecodeCommand(const void* data, std::size_t size, const BusOptions& options,
                                     const Eigen::Isometry3f& robot_from_camera, std::string* why) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  const std::string malformed = "malformed message (" + std::to_string(size) +
                                " bytes that do not decode as saccade.command_t";
  // lcm-gen's decoder trusts the string's length (0 or negative crash it): check the layout
  // before it runs.
  if (size < kCommandFixedBytes + 4 + 1 + kSignatureBytes) {
    Fail(why, malformed + ": too short)");
    return std::nullopt;
  }
  std::int32_t model_bytes = 0;
  for (int i = 0; i < 4; ++i)
    model_bytes = static_cast<std::int32_t>((static_cast<std::uint32_t>(model_bytes) << 8) |
                                            bytes[kCommandFixedBytes + i]);
  if (model_bytes < 1 || model_bytes > kMaxModelBytes ||
      size != kCommandFixedBytes + 4 + static_cast<std::size_t>(model_bytes) + kSignatureBytes ||
      bytes[size - kSignatureBytes - 1] != 0) {
    Fail(why, malformed + ": its model string's length is wrong)");
    return std::nullopt;
  }
  saccade::command_t m;
  try {
    if (m.decode(data, 0, static_cast<int>(size)) < 0) {
      Fail(why, malformed + ")");
      return std::nullopt;
    }
  } catch (const std::exception& e) {
    Fail(why, malformed + ": " + e.what() + ")");
    return std::nullopt;
  }
  Command c;
  switch (m.kind) {
    case saccade::command_t::SET_FOVEA: {
      const Eigen::Vector3f p(static_cast<float>(m.fovea[0]), static_cast<float>(m.fovea[1]),
                              static_cast<float>(m.fovea[2]));
      if (!p.allFinite()) {
        Fail(why, "SET_FOVEA with a non-finite fovea");
        return std::nullopt;
      }
      c.fovea_m = robot_from_camera.inverse() * p;
      if (!(c.fovea_m.norm() <= options.max_fovea_distance_m)) {
        char text[128];
        std::snprintf(text, sizeof text,
                      "SET_FOVEA out of range: %.2f m from the camera, more than %.2f m",
                      c.fovea_m.norm(), options.max_fovea_distance_m);
        Fail(why, text);
        return std::nullopt;
      }
      c.kind = Command::Kind::kSetFovea;
      break;
    }
    case saccade::command_t::RESET:
      c.kind = Command::Kind::kReset;
      break;
    case saccade::command_t::SWITCH_MODEL:
      if (m.model.empty()) {
        Fail(why, "SWITCH_MODEL without a model");
        return std::nullopt;
      }
      c.kind = Command::Kind::kSwitchModel;
      c.model = m.model;
      break;
    case saccade::command_t::PAUSE:
      c.kind = Command::Kind::kPause;
      break;
    case saccade::command_t::RESUME:
      c.kind = Command::Kind::kResume;
      break;
    default:
      Fail(why, "unknown kind " + std::to_string(m.kind));
      return std::nullopt;
  }
  return c;
}

namespace {

std::int64_t WallUtime() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

// The frame's utime on the wire: when it reached the host, in microseconds since the epoch. The
// steady clock measured how long ago that was; the wall clock says when now is.
std::int64_t ArrivalEpochUtime(std::int64_t arrival_steady_ns) {
  const std::int64_t now = WallUtime();
  if (arrival_steady_ns <= 0) return now;
  return now - std::max<std::int64_t>(0, (SteadyNowNs() - arrival_steady_ns) / 1000);
}

template <typename Vec>
void Copy3(const Vec& v, double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = v[i];
}

class LcmBus : public Bus {
 public:
  LcmBus(const BusOptions& options, BusOptions::Commands mode, std::unique_ptr<lcm::LCM> lcm,
         std::vector<std::unique_ptr<MessageMirror>> mirrors)
      : options_(options), mode_(mode), lcm_(std::move(lcm)), mirrors_(std::move(mirrors)) {
    frame_name_ = options_.robot.enabled ? options_.robot.name : "camera";
    detections_channel_ = DetectionsChannel(options_.channel_prefix);
    fixation_channel_ = FixationChannel(options_.channel_prefix);
    status_channel_ = StatusChannel(options_.channel_prefix);
    preview_channel_ = PreviewChannel(options_.channel_prefix);
    X_RC_ =
        options_.robot.enabled ? options_.robot.RobotFromCamera() : Eigen::Isometry3f::Identity();
  }

  // The command thread's wake pipe, made at open so that a failure is an open error.
  bool MakeWakePipe(std::string* error) {
    if (pipe(wake_) == 0) return true;
    return Fail(error, "cannot create the command thread's wake pipe");
  }

  // With commands signed, the gate every command passes first.
  void Guard(std::unique_ptr<CommandGate> gate) { gate_ = std::move(gate); }

  void Subscribe(CommandHandler handler) override {
    if (mode_ == BusOptions::Commands::kOff || receiver_.joinable()) return;
    on_command_ = std::move(handler);
    lcm_->subscribe(CommandChannel(options_.channel_prefix), &LcmBus::OnCommand, this);
    receiver_ = std::thread([this] { Receive(); });
  }

  ~LcmBus() override {
    if (receiver_.joinable()) {
      stop_ = true;
      const char byte = 0;
      [[maybe_unused]] const auto n = write(wake_[1], &byte, 1);
      receiver_.join();
    }
    for (int fd : wake_)
      if (fd >= 0) close(fd);
  }

  bool Publish(const FrameDetections& frame, const Fixation& fixation) override {
    saccade::detections_t d;
    d.utime = ArrivalEpochUtime(frame.arrival_steady_ns);
    d.sensor_utime = frame.capture_utime;
    d.seq = frame.seq;
    d.publish_utime = WallUtime();
    d.frame = frame_name_;
    d.foveated = frame.foveated;
    Copy3(X_RC_ * frame.fovea_m, d.fovea);
    d.growth = frame.growth_m;
    d.fixation_seq = frame.fixation_seq;
    d.recognize_ms = frame.recognize_ms;
    d.track_ms = frame.track_ms;
    for (const Detection& r : frame.instances) {
      saccade::instance_t i;
      i.utime = d.utime;
      i.model = r.model;
      if (r.model >= 0 && r.model < static_cast<int>(frame.models.size()))
        i.model_name = frame.models[static_cast<std::size_t>(r.model)];
      const Eigen::Isometry3f X_RM = X_RC_ * Eigen::Isometry3f(r.model_to_scene);
      Copy3(X_RM.translation(), i.trans);
      const Eigen::Quaternionf q(X_RM.rotation());
      i.quat[0] = q.w(), i.quat[1] = q.x(), i.quat[2] = q.y(), i.quat[3] = q.z();
      Copy3(X_RC_ * r.centroid_m, i.centroid);
      const bool sized = r.model >= 0 && r.model < static_cast<int>(frame.model_extents_m.size());
      Copy3(sized ? frame.model_extents_m[static_cast<std::size_t>(r.model)]
                  : Eigen::Vector3f::Zero().eval(),
            i.size);
      i.votes = r.votes;
      i.confidence = r.confidence;
      i.fitness = r.fitness;
      i.coverage = r.coverage;
      i.colour_agreement = r.colour_agreement;
      i.track_id = r.track_id;
      i.track_state = static_cast<std::int8_t>(r.track_state);
      i.track_state_name = TrackStateName(r.track_state);
      d.instances.push_back(i);
    }
    d.num_instances = static_cast<std::int32_t>(d.instances.size());

    saccade::fixation_t f;
    f.utime = d.utime;
    f.sensor_utime = frame.capture_utime;
    f.seq = fixation.frame_seq;
    f.frame = frame_name_;
    Copy3(X_RC_ * fixation.fovea_m, f.fovea);
    Copy3(X_RC_.linear() * fixation.velocity_mps, f.velocity);
    f.growth = fixation.growth_m;
    f.mode = static_cast<std::int8_t>(fixation.mode);
    f.mode_name = ModeName(fixation.mode);
    f.target = fixation.target;
    f.model = fixation.model;
    f.num_targets = fixation.num_targets;
    f.reason = fixation.reason;

    std::lock_guard<std::mutex> lock(publish_mutex_);
    const bool ok = lcm_->publish(detections_channel_, &d) == 0;
    for (const auto& mirror : mirrors_) mirror->Publish(d, f);
    return lcm_->publish(fixation_channel_, &f) == 0 && ok;
  }

  bool PublishStatus(const StatusReport& s) override {
    saccade::status_t m;
    m.utime = WallUtime();
    m.uptime_s = s.uptime_s;
    m.source = s.source;
    m.source_state = s.source_state;
    m.paused = s.paused;
    m.frames_in = s.frames_in;
    m.frames_processed = s.frames_processed;
    m.frames_dropped = s.frames_dropped;
    m.frames_skipped = s.frames_skipped;
    m.frames_unsent = s.frames_unsent;
    m.source_reconnects = s.source_reconnects;
    m.fps = s.fps;
    m.commands_accepted = s.commands_accepted;
    m.commands_rejected = s.commands_rejected;
    m.lcm_datagrams_dropped = s.lcm_datagrams_dropped;
    m.fixation_lag_max = s.fixation_lag_max;
    m.mode = static_cast<std::int8_t>(s.mode);
    for (const LatencyReport& l : s.stages) {
      saccade::stage_latency_t st;
      st.utime = m.utime;
      st.name = l.name;
      st.samples = l.samples;
      st.p50_ms = l.p50_ms, st.p90_ms = l.p90_ms, st.p99_ms = l.p99_ms, st.max_ms = l.max_ms;
      m.stages.push_back(st);
    }
    m.num_stages = static_cast<std::int32_t>(m.stages.size());
    std::lock_guard<std::mutex> lock(publish_mutex_);
    for (const auto& mirror : mirrors_) mirror->PublishStatus(m);
    return lcm_->publish(status_channel_, &m) == 0;
  }

  bool PublishPreview(const Preview& preview, std::int64_t arrival_steady_ns,
                      const PreviewOptions& options, std::string* error) override {
    const std::vector<std::uint8_t> bytes =
        EncodePreview(preview, ArrivalEpochUtime(arrival_steady_ns), options, error);
    if (bytes.empty()) return false;
    std::lock_guard<std::mutex> lock(publish_mutex_);
    for (const auto& mirror : mirrors_) mirror->PublishPreview(bytes);
    if (lcm_->publish(preview_channel_, bytes.data(), static_cast<unsigned>(bytes.size())) == 0)
      return true;
    return Fail(error, "preview: LCM did not send it");
  }

  std::int64_t AcceptedCommands() const override { return accepted_; }
  std::int64_t RejectedCommands() const override { return rejected_; }
  std::int64_t DroppedDatagrams() const override { return LcmDatagramsDropped(options_.url); }

  std::string Describe() const override {
    std::string commands = "off";
    if (mode_ == BusOptions::Commands::kSigned)
      commands = "signed with " + options_.command_key;
    else if (mode_ == BusOptions::Commands::kOpen)
      commands = "open to this host";
    std::string text =
        options_.url + " (channels " + options_.channel_prefix + "_*, commands " + commands + ")";
    for (const auto& mirror : mirrors_) text += "; " + mirror->Describe();
    return text;
  }

 private:
  void Receive() {
    pollfd fds[2] = {{lcm_->getFileno(), POLLIN, 0}, {wake_[0], POLLIN, 0}};
    while (!stop_) {
      if (poll(fds, 2, -1) < 0) continue;  // EINTR
      if (fds[0].revents & (POLLERR | POLLHUP | POLLNVAL)) {
        // A dead socket would wake poll forever: stop listening, keep publishing.
        Log(LogLevel::kError, "LCM: the command socket failed; commands are off from now on");
        return;
      }
      if ((fds[0].revents & POLLIN) && lcm_->handle() != 0)
        Log(LogLevel::kWarning, "LCM: a message could not be received");
    }
  }

  // Counts a rejected command and logs why, at most 5 lines a second (the next line logged
  // says how many went unsaid): a flood of bad commands must not flood the log. Any thread.
  void Reject(const std::string& why) {
    ++rejected_;
    std::int64_t unsaid = 0;
    if (!reject_log_.Allow(&unsaid)) return;
    std::string line =
        "command rejected on " + CommandChannel(options_.channel_prefix) + ": " + why;
    if (unsaid > 0) line += " (" + std::to_string(unsaid) + " more rejected before it, unlogged)";
    Log(LogLevel::kWarning, line);
  }

  void OnCommand(const lcm::ReceiveBuffer* rbuf, const std::string& /*channel*/) {
    std::string why;
    // The signature first: nothing of an unsigned command is read.
    if (gate_ && !gate_->Admit(rbuf->data, rbuf->data_size, &why)) return Reject(why);
    const std::optional<Command> c =
        DecodeCommand(rbuf->data, rbuf->data_size, options_, X_RC_, &why);
    if (!c) return Reject(why);
    on_command_(*c, [this](bool accepted, const std::string& why) {
      if (accepted)
        ++accepted_;
      else
        Reject(why);
    });
  }

  const BusOptions options_;
  const BusOptions::Commands mode_;
  std::unique_ptr<CommandGate> gate_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::vector<std::unique_ptr<MessageMirror>> mirrors_;  // called under publish_mutex_
  std::string frame_name_;
  std::string detections_channel_, fixation_channel_, status_channel_, preview_channel_;
  Eigen::Isometry3f X_RC_;
  std::mutex publish_mutex_;
  CommandHandler on_command_;
  std::atomic<std::int64_t> accepted_{0};
  std::atomic<std::int64_t> rejected_{0};
  LogLimiter reject_log_{5};
  std::atomic<bool> stop_{false};
  int wake_[2] = {-1, -1};
  std::thread receiver_;
};

}  // namespace

bool RobotFrameOptions::IsValid(std::string* error) const {
  if (name.empty()) return Fail(error, "name must not be empty");
  if (!translation_m.allFinite()) return Fail(error, "translation_m must be finite");
  if (!rotation.coeffs().allFinite() || std::abs(rotation.norm() - 1.0f) > 1e-3f)
    return Fail(error, "rotation must be a unit quaternion [w, x, y, z]");
  return true;
}

namespace {

// The multicast TTL of an LCM URL: udpm's ttl option (liblcm's default 0); 0 for a provider that
// never leaves the host (memq://, file://).
int UrlTtl(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0 && url.rfind("udp://", 0) != 0) return 0;
  const std::size_t query = url.find('?');
  if (query == std::string::npos) return 0;
  std::size_t at = query + 1;
  while (at < url.size()) {
    const std::size_t end = std::min(url.find('&', at), url.size());
    const std::string option = url.substr(at, end - at);
    if (option.rfind("ttl=", 0) == 0) return std::atoi(option.c_str() + 4);
    at = end + 1;
  }
  return 0;
}

}  // namespace

BusOptions::Commands BusOptions::Resolved() const {
  if (commands != Commands::kAuto) return commands;
  if (PathExists(command_key)) return Commands::kSigned;
  return UrlTtl(url) == 0 ? Commands::kOpen : Commands::kOff;
}

bool BusOptions::IsValid(std::string* error) const {
  if (url.empty()) return Fail(error, "url must not be empty");
  if (commands == Commands::kOpen && UrlTtl(url) != 0)
    return Fail(error,
                "commands: open lets anyone the network reaches command saccaded; it is "
                "allowed only with ttl=0 in the url (make a key with saccade keygen and "
                "use signed)");
  if (command_key.empty()) return Fail(error, "command_key must not be empty");
  if (!(command_max_age_s > 0 && command_max_age_s <= 3600))
    return Fail(error, "command_max_age_s must be in (0, 3600]");
  // LCM refuses channel names of 64 bytes or more, the longest being PREFIX_DETECTIONS.
  if (channel_prefix.empty() || channel_prefix.size() > 52)
    return Fail(error, "channel_prefix must be 1 to 52 characters (LCM channels are under 64)");
  if (!(max_fovea_distance_m > 0)) return Fail(error, "max_fovea_distance_m must be > 0");
  return true;
}

std::unique_ptr<Bus> OpenLcmBus(const BusOptions& options, std::string* error,
                                std::vector<std::unique_ptr<MessageMirror>> mirrors) {
  std::unique_ptr<lcm::LCM> lcm = OpenLcm(options.url, error);
  if (!lcm) return nullptr;
  const BusOptions::Commands mode = options.Resolved();
  auto bus = std::make_unique<LcmBus>(options, mode, std::move(lcm), std::move(mirrors));
  if (mode == BusOptions::Commands::kOff) {
    if (options.commands == BusOptions::Commands::kAuto)
      Log(LogLevel::kWarning, "commands are off: no key at " + options.command_key +
                                  " and the LCM url reaches beyond this host (ttl > 0); "
                                  "saccade keygen makes one (docs/LCM.md)");
    return bus;
  }
  if (mode == BusOptions::Commands::kSigned) {
    Digest key{};
    if (!ReadCommandKey(options.command_key, &key, error)) return nullptr;
    bus->Guard(std::make_unique<CommandGate>(key, options.command_max_age_s, WallUtime));
  }
  if (!bus->MakeWakePipe(error)) return nullptr;
  return bus;
}

}  // namespace saccade
