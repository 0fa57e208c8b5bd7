#include "io/sources/frame_source.h"

#include "core/fail.h"

#include "core/features.h"
#include "io/base/log.h"
#include "io/base/text.h"
#include "io/config/config.h"
#include "io/formats/cloud_io.h"
#include "io/formats/images.h"
#include "io/formats/truth_file.h"
#include "io/sources/freenect_source.h"
#include "io/sources/mailbox.h"
#include "io/sources/openni2_source.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <thread>

namespace saccade {

namespace fs = std::filesystem;

namespace {

// A finite, indexable sequence of frames (files or a scenario), read on demand.
class Sequence {
 public:
  virtual ~Sequence() = default;
  virtual std::size_t size() const = 0;
  /// Frame `i` (0 <= i < size()); capture_utime relative to the sequence's start.
  virtual bool Read(std::size_t i, Frame* frame, std::string* error) const = 0;
  virtual std::string Describe() const = 0;
  /// The sequence's own frame clock: frame i is captured at i / clock_hz(), and a loop's next
  /// pass continues from where the last one ended.
  virtual double clock_hz() const = 0;
};

// Plays a Sequence: once or looping; paced at `rate_hz` on its own thread into a latest-frame
// mailbox (live), or as fast as the consumer asks (rate 0).
class SequenceSource : public FrameSource {
 public:
  SequenceSource(std::unique_ptr<Sequence> sequence, double rate_hz, bool loop)
      : sequence_(std::move(sequence)), rate_hz_(rate_hz), loop_(loop) {
    if (Live()) producer_ = std::thread([this] { Produce(); });
  }
  ~SequenceSource() override {
    Stop();
    if (producer_.joinable()) producer_.join();
  }

  Status Next(Frame* frame, std::string* error) override {
    if (!Live()) {
      if (stopped_) return Status::kEnd;
      const Status s = ReadNext(frame, error);
      if (s == Status::kEnd) SetState("ended");
      return s;
    }
    auto item = mailbox_.Take();
    if (!item) return Status::kEnd;
    if (item->status == Status::kFrame) *frame = std::move(item->frame);
    if (item->status == Status::kError) Fail(error, item->error);
    return item->status;
  }

  void Stop() override {
    stopped_ = true;
    mailbox_.CloseAndClear();
  }

  SourceStats Stats() const override {
    SourceStats s;
    s.produced = produced_;
    s.dropped = mailbox_.dropped();
    s.skipped = skipped_;
    std::lock_guard<std::mutex> lock(state_mutex_);
    s.state = state_;
    return s;
  }

  bool Live() const override { return rate_hz_ > 0; }
  std::string Describe() const override { return sequence_->Describe(); }

 private:
  struct Item {
    Status status = Status::kFrame;
    Frame frame;
    std::string error;
  };

  void SetState(const std::string& state) {
    std::lock_guard<std::mutex> lock(state_mutex_);
    state_ = state;
  }

  // A frame that cannot be used (a corrupt or truncated file, too few points for intrinsics)
  // is skipped and counted, as a camera drops one, and its sequence number stays unused; it is
  // named in the log on the first pass. A whole pass without one usable frame is an error, not
  // a loop without end.
  Status ReadNext(Frame* frame, std::string* error) {
    const std::size_t n = sequence_->size();
    for (std::size_t failed = 0;;) {
      if (next_ >= n && !loop_) return Status::kEnd;
      const std::size_t pass = next_ / n, i = next_ % n;
      std::string why;
      if (sequence_->Read(i, frame, &why)) {
        // Each pass through a loop continues the clock where the last one ended.
        frame->capture_utime += std::llround(pass * n * 1e6 / sequence_->clock_hz());
        frame->sequence = next_++;
        ++produced_;
        return Status::kFrame;
      }
      ++next_;
      if (++failed == n) {
        SetState("error");
        Fail(error, why + (n == 1 ? "" : " (no frame of " + sequence_->Describe() + " is usable)"));
        return Status::kError;
      }
      ++skipped_;
      if (pass == 0) Log(LogLevel::kWarning, "skipping an unusable frame: " + why);
    }
  }

  void Produce() {
    using Clock = std::chrono::steady_clock;
    const auto period = std::chrono::duration<double>(1.0 / rate_hz_);
    auto due = Clock::now();
    while (!stopped_) {
      Item item;
      item.status = ReadNext(&item.frame, &item.error);
      if (item.status != Status::kFrame) {
        SetState(item.status == Status::kEnd ? "ended" : "error: " + item.error);
        if (item.status == Status::kError) mailbox_.Put(std::move(item));
        mailbox_.Close();
        return;
      }
      // A sensor's clock, not the reader's: wait for this frame's moment, then publish.
      due += std::chrono::duration_cast<Clock::duration>(period);
      std::this_thread::sleep_until(due);
      item.frame.arrival_steady_ns = SteadyNowNs();
      mailbox_.Put(std::move(item));
    }
  }

  std::unique_ptr<Sequence> sequence_;
  const double rate_hz_;
  const bool loop_;
  std::atomic<bool> stopped_{false};
  std::size_t next_ = 0;  // only the producer (live) or the consumer (not live) touches it
  std::atomic<std::uint64_t> produced_{0}, skipped_{0};
  LatestMailbox<Item> mailbox_;
  mutable std::mutex state_mutex_;
  std::string state_ = "streaming";
  std::thread producer_;
};

// PCD files of a folder, in name order.
std::vector<std::string> ListPcdFiles(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& path : RegularFilesIn(dir))
    if (EndsWith(fs::path(path).filename().string(), ".pcd")) out.push_back(path);
  return out;
}

// Ground truth recorded beside files (truth.csv), by row; none when there is no such file.
// nullopt with `error` when the file is malformed.
std::optional<std::vector<std::optional<GroundTruth>>> TruthBeside(const std::string& dir,
                                                                   std::size_t n,
                                                                   std::string* error) {
  std::vector<std::optional<GroundTruth>> truth(n);
  const std::string path = (fs::path(dir) / kTruthFileName).string();
  if (!PathExists(path)) return truth;
  std::vector<TruthRow> rows;
  if (!ReadTruthFile(path, &rows, error)) return std::nullopt;
  for (std::size_t i = 0; i < rows.size() && i < n; ++i) truth[i] = rows[i].truth;
  return truth;
}

// Frames stored one per file in a folder, with their truth beside them. The clock is the
// rate the files are played at, 30 Hz when they are read as fast as possible.
class FolderSequence : public Sequence {
 public:
  FolderSequence(std::string kind, std::string dir, std::vector<std::string> files,
                 std::vector<std::optional<GroundTruth>> truth, double rate_hz)
      : kind_(std::move(kind)),
        dir_(std::move(dir)),
        files_(std::move(files)),
        truth_(std::move(truth)),
        clock_hz_(rate_hz > 0 ? rate_hz : 30.0) {}
  std::size_t size() const override { return files_.size(); }
  double clock_hz() const override { return clock_hz_; }
  std::string Describe() const override {
    return kind_ + ":" + dir_ + " (" + std::to_string(files_.size()) + " frames)";
  }

 protected:
  // Sets what every folder frame has besides its cloud: intrinsics, time and truth.
  void Stamp(std::size_t i, const CameraIntrinsics& k, Cloud cloud, Frame* frame) const {
    frame->intrinsics = k;
    frame->cloud = std::make_shared<const Cloud>(std::move(cloud));
    frame->capture_utime = std::llround(i * 1e6 / clock_hz_);
    frame->truth = truth_[i];
  }
  const std::string& file(std::size_t i) const { return files_[i]; }

 private:
  std::string kind_, dir_;
  std::vector<std::string> files_;
  std::vector<std::optional<GroundTruth>> truth_;
  double clock_hz_;
};

class PcdSequence : public FolderSequence {
 public:
  using FolderSequence::FolderSequence;
  bool Read(std::size_t i, Frame* frame, std::string* error) const override {
    auto cloud = LoadCloud(file(i), error);
    if (!cloud) return false;
    if (cloud->height <= 1) return Fail(error, file(i) + ": not an organized cloud (height 1)");
    const auto k = EstimateIntrinsics(*cloud);
    if (!k) return Fail(error, file(i) + ": cannot estimate intrinsics (too few points)");
    Stamp(i, *k, std::move(*cloud), frame);
    return true;
  }
};

class DepthSequence : public FolderSequence {
 public:
  DepthSequence(std::string dir, std::vector<std::string> depth,
                std::vector<std::optional<GroundTruth>> truth, double rate_hz, CameraIntrinsics k)
      : FolderSequence("depth", std::move(dir), std::move(depth), std::move(truth), rate_hz),
        k_(k) {}
  bool Read(std::size_t i, Frame* frame, std::string* error) const override {
    DepthImage depth;
    if (!ReadDepthImage(file(i), &depth, error)) return false;
    if (depth.width != k_.width || depth.height != k_.height)
      return Fail(error, file(i) + ": image is " + std::to_string(depth.width) + "x" +
                             std::to_string(depth.height) + ", intrinsics say " +
                             std::to_string(k_.width) + "x" + std::to_string(k_.height));
    RgbImage rgb;
    const std::string rgb_path = RgbPartner(file(i));
    if (!rgb_path.empty()) {
      if (!ReadRgbImage(rgb_path, &rgb, error)) return false;
      if (rgb.width != depth.width || rgb.height != depth.height)
        return Fail(error, rgb_path + ": colour image size differs from its depth image");
    }
    Stamp(i, k_, DepthToCloud(depth.data.data(), rgb.data.empty() ? nullptr : rgb.data.data(), k_),
          frame);
    return true;
  }

 private:
  CameraIntrinsics k_;
};

class ScenarioSequence : public Sequence {
 public:
  explicit ScenarioSequence(Scenario s) : s_(std::move(s)) {}
  std::size_t size() const override { return static_cast<std::size_t>(s_.frames); }
  bool Read(std::size_t i, Frame* frame, std::string*) const override {
    ScenarioFrame f = RenderScenarioFrame(s_, static_cast<int>(i), k_);
    frame->intrinsics = k_;
    frame->cloud = std::make_shared<const Cloud>(std::move(f.rendered.cloud));
    frame->capture_utime = static_cast<std::int64_t>(std::llround(f.time_s * 1e6));
    frame->truth = f.truth;
    return true;
  }
  double clock_hz() const override { return s_.rate_hz; }
  std::string Describe() const override {
    return "synthetic:" + s_.name + " (" + std::to_string(s_.frames) + " frames, seed " +
           std::to_string(s_.seed) + ")";
  }

 private:
  Scenario s_;
  CameraIntrinsics k_;
};

// A real capture seen again from a moving virtual camera, its object moving (capture:FILE.yaml).
class CaptureFrames : public Sequence {
 public:
  CaptureFrames(CaptureSequence s, LoadedCapture capture)
      : s_(std::move(s)), capture_(std::move(capture)) {}
  std::size_t size() const override { return static_cast<std::size_t>(s_.frames); }
  bool Read(std::size_t i, Frame* frame, std::string*) const override {
    CaptureFrame f = RenderCaptureFrame(s_, capture_, static_cast<int>(i));
    frame->intrinsics = capture_.intrinsics;
    frame->cloud = std::make_shared<const Cloud>(std::move(f.cloud));
    frame->capture_utime = static_cast<std::int64_t>(std::llround(f.time_s * 1e6));
    frame->truth = f.truth;
    return true;
  }
  double clock_hz() const override { return s_.rate_hz; }
  std::string Describe() const override {
    return "capture:" + s_.name + " (" + s_.capture + ", object " + std::to_string(s_.object) +
           ", " + std::to_string(s_.frames) + " frames)";
  }

 private:
  CaptureSequence s_;
  LoadedCapture capture_;
};

// The spec as the user wrote it, without its options.
std::string SpecText(const SourceSpec& spec) {
  if (spec.kind == "openni2" || spec.kind == "freenect") return spec.kind + "://" + spec.target;
  if (spec.kind == "oni") return spec.target;
  return spec.kind + ":" + spec.target;
}

// A number as a person would write it (1e+20, 2.5, 7).
std::string FormatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// Typed option readers: false with an error naming the spec and the option.
bool OptionNumber(const SourceSpec& spec, const std::string& key, double fallback, double* out,
                  std::string* error) {
  auto it = spec.options.find(key);
  if (it == spec.options.end()) {
    *out = fallback;
    return true;
  }
  char* end = nullptr;
  *out = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0' || !std::isfinite(*out) || *out < 0)
    return Fail(error, "source '" + SpecText(spec) + "': option " + key + "=" + it->second +
                           " is not a number >= 0");
  return true;
}

// rate=HZ: 0 (as fast as frames come) or 0.01-1000 Hz. A tinier rate would wait for ages
// between frames (1e-300: for ever), a huge one is no rate.
// (A scenario's or a sequence's own rate_hz, the fallback, is bounded by its IsValid.)
bool OptionRate(const SourceSpec& spec, double fallback, double* out, std::string* error) {
  if (!OptionNumber(spec, "rate", fallback, out, error)) return false;
  const auto given = spec.options.find("rate");
  if (given != spec.options.end() && *out != 0 && (*out < 0.01 || *out > 1000))
    return Fail(error, "source '" + SpecText(spec) + "': option rate=" + given->second +
                           " is out of range (0: as fast as frames come, or 0.01-1000 Hz)");
  return true;
}

// frames=N: a whole number, 1 to kMaxSequenceFrames.
bool OptionFrames(const SourceSpec& spec, int fallback, int* out, std::string* error) {
  double frames = fallback;
  if (!OptionNumber(spec, "frames", fallback, &frames, error)) return false;
  if (frames < 1 || frames > kMaxSequenceFrames || frames != std::floor(frames))
    return Fail(error, "source '" + SpecText(spec) + "': frames=" + FormatNumber(frames) +
                           " must be a whole number, 1-" + std::to_string(kMaxSequenceFrames));
  *out = static_cast<int>(frames);
  return true;
}

bool OptionBool(const SourceSpec& spec, const std::string& key, bool* out, std::string* error) {
  auto it = spec.options.find(key);
  if (it == spec.options.end()) return true;
  if (it->second == "1" || it->second == "true") {
    *out = true;
  } else if (it->second == "0" || it->second == "false") {
    *out = false;
  } else {
    return Fail(error, "source '" + SpecText(spec) + "': option " + key + "=" + it->second +
                           " is not 0/1/true/false");
  }
  return true;
}

bool OnlyOptions(const SourceSpec& spec, std::initializer_list<const char*> allowed,
                 std::string* error) {
  for (const auto& option : spec.options) {
    const std::string& key = option.first;  // a named copy: C++17 lambdas cannot capture a binding
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }))
      return Fail(error, "source '" + SpecText(spec) + "': unknown option '" + key + "'");
  }
  return true;
}

std::unique_ptr<FrameSource> OpenFiles(const SourceSpec& spec, std::string* error) {
  double rate = 0;
  bool loop = false;
  if (!OnlyOptions(spec, {"rate", "loop", "intrinsics"}, error) ||
      !OptionRate(spec, 0, &rate, error) || !OptionBool(spec, "loop", &loop, error))
    return nullptr;
  if (spec.kind == "pcd" && spec.options.count("intrinsics")) {
    Fail(error, "source 'pcd:" + spec.target + "': option 'intrinsics' is for depth: sources");
    return nullptr;
  }
  // pcd: one PCD file is a sequence of one frame (loop=1 repeats it), a folder its files.
  std::error_code ec;
  const bool one_file = spec.kind == "pcd" && fs::is_regular_file(spec.target, ec) &&
                        EndsWith(fs::path(spec.target).filename().string(), ".pcd");
  if (!one_file && !IsDirectory(spec.target)) {
    Fail(error, spec.target +
                    (spec.kind == "pcd" ? ": no such folder or .pcd file" : ": no such folder") +
                    " (source '" + spec.kind + ":" + spec.target + "')");
    return nullptr;
  }
  std::vector<std::string> files = one_file             ? std::vector<std::string>{spec.target}
                                   : spec.kind == "pcd" ? ListPcdFiles(spec.target)
                                                        : ListDepthImages(spec.target);
  if (files.empty()) {
    Fail(error, spec.target + (spec.kind == "pcd"
                                   ? ": no .pcd file in the folder"
                                   : ": no depth image (PNG or TIFF named *depth*) in the folder"));
    return nullptr;
  }
  // One file takes its row of the recording's truth, when it is one of a recording's files.
  const fs::path parent = fs::path(spec.target).parent_path();
  const std::string truth_dir = one_file ? (parent.empty() ? "." : parent.string()) : spec.target;
  const std::vector<std::string> siblings = one_file ? ListPcdFiles(truth_dir) : files;
  auto truth = TruthBeside(truth_dir, siblings.size(), error);
  if (!truth) return nullptr;
  if (one_file) {
    const auto at = std::find_if(siblings.begin(), siblings.end(), [&](const std::string& f) {
      return fs::equivalent(f, spec.target, ec);
    });
    const std::optional<GroundTruth> row =
        at != siblings.end() ? (*truth)[std::size_t(at - siblings.begin())] : std::nullopt;
    truth->assign(1, row);
  }
  std::unique_ptr<Sequence> sequence;
  if (spec.kind == "pcd") {
    sequence = std::make_unique<PcdSequence>("pcd", spec.target, std::move(files),
                                             std::move(*truth), rate);
  } else {
    const auto it = spec.options.find("intrinsics");
    const std::string k_path = it != spec.options.end()
                                   ? it->second
                                   : (fs::path(spec.target) / "intrinsics.yaml").string();
    IntrinsicsFile kf;
    if (!ReadIntrinsicsFile(k_path, &kf, error)) return nullptr;
    sequence = std::make_unique<DepthSequence>(spec.target, std::move(files), std::move(*truth),
                                               rate, kf.Camera());
  }
  return std::make_unique<SequenceSource>(std::move(sequence), rate, loop);
}

std::unique_ptr<FrameSource> OpenSynthetic(const SourceSpec& spec, std::string* error) {
  if (!OnlyOptions(spec, {"rate", "loop", "frames", "seed"}, error)) return nullptr;
  Scenario scenario;
  if (auto preset = ScenarioPreset(spec.target)) {
    scenario = *preset;
  } else if (EndsWith(spec.target, ".yaml") || EndsWith(spec.target, ".yml") ||
             PathExists(spec.target)) {
    if (!LoadScenario(spec.target, &scenario, error)) return nullptr;
  } else {
    std::string names;
    for (const auto& n : ScenarioPresetNames()) names += (names.empty() ? "" : ", ") + n;
    Fail(error, "source 'synthetic:" + spec.target + "': no such scenario (presets: " + names +
                    "; or a YAML file)");
    return nullptr;
  }
  double rate = scenario.rate_hz, seed = scenario.seed;
  bool loop = false;
  if (!OptionRate(spec, scenario.rate_hz, &rate, error) ||
      !OptionFrames(spec, scenario.frames, &scenario.frames, error) ||
      !OptionNumber(spec, "seed", scenario.seed, &seed, error) ||
      !OptionBool(spec, "loop", &loop, error))
    return nullptr;
  if (seed != std::floor(seed) || seed > 4294967295.0) {
    Fail(error, "source '" + SpecText(spec) + "': seed=" + FormatNumber(seed) +
                    " must be a whole number, 0-4294967295");
    return nullptr;
  }
  scenario.seed = static_cast<std::uint32_t>(seed);
  if (rate > 0) scenario.rate_hz = rate;  // the scene's clock follows the sensor's
  return std::make_unique<SequenceSource>(std::make_unique<ScenarioSequence>(scenario), rate, loop);
}

// The sequence file of a capture: spec and the capture it names, loaded with its object's
// points. DIR (the data option, default ../shared/data) resolves a relative capture path.
bool LoadCapture(const SourceSpec& spec, CaptureSequence* s, LoadedCapture* capture,
                 std::string* error) {
  s->name = fs::path(spec.target).stem().string();
  if (!LoadCaptureSequence(spec.target, s, error)) return false;
  const auto data = spec.options.find("data");
  const std::string dir = data != spec.options.end() ? data->second : "../shared/data";
  const std::string file = s->capture[0] == '/' ? s->capture : dir + "/" + s->capture;
  std::optional<LabelledCloud> labelled = LoadLabelledCloud(file, error);
  if (!labelled) return false;
  const auto k = EstimateIntrinsics(labelled->cloud);
  if (!k) return Fail(error, file + ": not an organized capture (no intrinsics can be estimated)");
  capture->intrinsics = *k;
  // The object's points and centroid, or a one-line error naming the file and the object.
  const auto points_of = [&](int object, std::vector<int>* points, Eigen::Vector3f* centroid) {
    *points = MosdObjectPoints(labelled->cloud, labelled->labels, object);
    if (points->empty())
      return Fail(error, file + ": no object " + std::to_string(object) + " (labels " +
                             std::to_string(10 * object) + "-" + std::to_string(10 * object + 9) +
                             ")");
    *centroid = Eigen::Vector3f::Zero();
    for (int i : *points) *centroid += labelled->cloud[std::size_t(i)].getVector3fMap();
    *centroid /= static_cast<float>(points->size());
    return true;
  };
  if (!points_of(s->object, &capture->object, &capture->object_centroid)) return false;
  capture->others.resize(s->others.size());
  capture->other_centroids.resize(s->others.size());
  for (std::size_t j = 0; j < s->others.size(); ++j)
    if (!points_of(s->others[j], &capture->others[j], &capture->other_centroids[j])) return false;
  capture->cloud = std::move(labelled->cloud);
  return true;
}

// capture:FILE.yaml[?data=DIR&frames=N&rate=HZ&loop=0|1]: a CaptureSequence file; its capture
// is resolved against DIR (default ../shared/data) unless absolute.
std::unique_ptr<FrameSource> OpenCapture(const SourceSpec& spec, std::string* error) {
  if (!OnlyOptions(spec, {"rate", "loop", "frames", "data"}, error)) return nullptr;
  CaptureSequence s;
  LoadedCapture capture;
  if (!LoadCapture(spec, &s, &capture, error)) return nullptr;
  double rate = s.rate_hz;
  bool loop = false;
  if (!OptionRate(spec, s.rate_hz, &rate, error) ||
      !OptionFrames(spec, s.frames, &s.frames, error) || !OptionBool(spec, "loop", &loop, error))
    return nullptr;
  if (rate > 0) s.rate_hz = rate;
  return std::make_unique<SequenceSource>(
      std::make_unique<CaptureFrames>(std::move(s), std::move(capture)), rate, loop);
}

}  // namespace

std::optional<Cloud> LoadCaptureModel(const std::string& text, std::string* error) {
  const std::optional<SourceSpec> spec = ParseSourceSpec(text, error);
  if (!spec) return std::nullopt;
  if (!OnlyOptions(*spec, {"data", "object"}, error)) return std::nullopt;
  CaptureSequence s;
  LoadedCapture capture;
  if (!LoadCapture(*spec, &s, &capture, error)) return std::nullopt;
  double object = s.object;
  if (!OptionNumber(*spec, "object", s.object, &object, error)) return std::nullopt;
  const std::vector<int>* points = object == s.object ? &capture.object : nullptr;
  for (std::size_t j = 0; j < s.others.size(); ++j)
    if (object == s.others[j]) points = &capture.others[j];
  if (!points) {
    Fail(error, "model '" + text + "': object " + spec->options.at("object") +
                    " is neither the sequence's object nor one of its others");
    return std::nullopt;
  }
  Cloud model;
  for (int i : *points) model.push_back(capture.cloud[std::size_t(i)]);
  return model;
}

std::optional<SourceSpec> ParseSourceSpec(const std::string& text, std::string* error) {
  // A spec is one line of printable text; a control character (a newline from a script, a NUL)
  // is refused before the spec is echoed in any message.
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02x", c);
      Fail(error, std::string("source: a control character (") + code + ") at byte " +
                      std::to_string(i) + " of the spec; a spec is one line of text");
      return std::nullopt;
    }
  }
  SourceSpec spec;
  std::string body = text, query;
  const auto q = text.find('?');
  if (q != std::string::npos) body = text.substr(0, q), query = text.substr(q + 1);
  if (body.rfind("openni2://", 0) == 0) {
    spec.kind = "openni2";
    spec.target = body.substr(10);
  } else if (body.rfind("freenect://", 0) == 0) {
    spec.kind = "freenect";
    spec.target = body.substr(11);
  } else if (EndsWith(body, ".oni")) {
    spec.kind = "oni";
    spec.target = body;
  } else {
    const auto colon = body.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == body.size()) {
      Fail(error, "source '" + text +
                      "': expected openni2://[DEVICE], freenect://[DEVICE], PATH.oni, pcd:DIR, "
                      "depth:DIR, synthetic:NAME or capture:FILE.yaml");
      return std::nullopt;
    }
    spec.kind = body.substr(0, colon);
    spec.target = body.substr(colon + 1);
    if (spec.kind != "pcd" && spec.kind != "depth" && spec.kind != "synthetic" &&
        spec.kind != "capture") {
      Fail(error, "source '" + text + "': unknown kind '" + spec.kind +
                      "' (openni2://, freenect://, .oni, pcd:, depth:, synthetic:, capture:)");
      return std::nullopt;
    }
  }
  std::size_t start = 0;
  while (!query.empty() && start <= query.size()) {
    const auto amp = std::min(query.find('&', start), query.size());
    const std::string pair = query.substr(start, amp - start);
    const auto eq = pair.find('=');
    if (eq == std::string::npos || eq == 0) {
      Fail(error, "source '" + text + "': option '" + pair + "' is not key=value");
      return std::nullopt;
    }
    spec.options[pair.substr(0, eq)] = pair.substr(eq + 1);
    start = amp + 1;
  }
  return spec;
}

std::unique_ptr<FrameSource> OpenSource(const std::string& text, std::string* error,
                                        double wait_at_start_s) {
  const auto spec = ParseSourceSpec(text, error);
  if (!spec) return nullptr;
  if (spec->kind == "pcd" || spec->kind == "depth") return OpenFiles(*spec, error);
  if (spec->kind == "synthetic") return OpenSynthetic(*spec, error);
  if (spec->kind == "capture") return OpenCapture(*spec, error);
  if (spec->kind == "freenect") {
    FreenectOptions o;
    if (!OnlyOptions(*spec, {"calibration", "raw"}, error) ||
        !OptionBool(*spec, "raw", &o.raw, error))
      return nullptr;
    const auto calibration = spec->options.find("calibration");
    if (calibration != spec->options.end()) o.calibration = calibration->second;
    return OpenFreenectDevice(spec->target, o, wait_at_start_s, error);
  }
  ColourOptions colour;
  if (spec->kind == "oni" || spec->kind == "openni2") {
    if (!OptionBool(*spec, "colour", &colour.enabled, error)) return nullptr;
    const auto registration = spec->options.find("registration");
    if (registration != spec->options.end()) {
      using R = ColourOptions::Registration;
      const std::map<std::string, R> names = {
          {"auto", R::kAuto}, {"device", R::kDevice}, {"saccade", R::kSaccade}, {"none", R::kNone}};
      const auto it = names.find(registration->second);
      if (it == names.end()) {
        Fail(error, "source '" + text + "': registration must be auto, device, saccade or none");
        return nullptr;
      }
      colour.registration = it->second;
    }
    const auto calibration = spec->options.find("calibration");
    if (calibration != spec->options.end()) colour.calibration = calibration->second;
  }
  if (spec->kind == "oni") {
    if (!OnlyOptions(*spec, {"mode", "loop", "colour", "registration", "calibration"}, error))
      return nullptr;
    OniPlaybackOptions o;
    if (!OptionBool(*spec, "loop", &o.loop, error)) return nullptr;
    const auto mode = spec->options.find("mode");
    if (mode != spec->options.end()) {
      if (mode->second == "realtime") {
        o.mode = OniPlaybackOptions::Mode::kRealtime;
      } else if (mode->second == "fast") {
        o.mode = OniPlaybackOptions::Mode::kFast;
      } else if (mode->second == "step") {
        o.mode = OniPlaybackOptions::Mode::kStep;
      } else {
        Fail(error, "source '" + text + "': mode must be realtime, fast or step");
        return nullptr;
      }
    }
    return OpenOniPlayback(spec->target, o, colour, error);
  }
  if (!OnlyOptions(*spec, {"colour", "registration", "calibration"}, error)) return nullptr;
  return OpenOpenNI2Device(spec->target, colour, wait_at_start_s, error);
}

}  // namespace saccade
