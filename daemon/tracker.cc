#include "daemon/tracker.h"

#include "core/recognition.h"
#include "core/saliency.h"
#include "daemon/tbb_parallel.h"
#include "io/bus.h"
#include "io/cloud_io.h"
#include "io/frame_source.h"
#include "io/log.h"

#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <thread>

namespace saccade {
namespace {

struct NamedModel {
  std::string name;
  ModelDescription description;
};
using Models = std::vector<std::shared_ptr<const NamedModel>>;

// What the recognize stage needs, swapped whole on reload or model switch.
struct Engine {
  RecognitionOptions recognition;
  FoveaOptions fovea;
  SaliencyOptions saliency;
  bool saccade_fallback = false;
  float predict_max_horizon_s = 0;
  Models models;
};

std::optional<Models> DescribeModels(const std::vector<std::string>& specs,
                                     const RecognitionOptions& options, std::string* error) {
  Models models;
  for (const std::string& spec : specs) {
    std::optional<Cloud> cloud = LoadModelCloud(spec, error);
    if (!cloud) return std::nullopt;
    std::string why;
    std::optional<ModelDescription> d = DescribeModel(*cloud, options, &why);
    if (!d) {
      *error = "model '" + spec + "': " + why;
      return std::nullopt;
    }
    models.push_back(std::make_shared<const NamedModel>(NamedModel{spec, std::move(*d)}));
  }
  return models;
}

bool SameModelRadii(const RecognitionOptions& a, const RecognitionOptions& b) {
  return a.model_normal_neighbors == b.model_normal_neighbors &&
         a.model_keypoint_radius_m == b.model_keypoint_radius_m &&
         a.model_shot_radius_m == b.model_shot_radius_m &&
         a.model_lrf_radius_m == b.model_lrf_radius_m && a.match_branching == b.match_branching &&
         a.match_checks == b.match_checks && a.match_seed == b.match_seed &&
         a.vote_for_model_origin == b.vote_for_model_origin &&
         a.radii_from_model == b.radii_from_model && a.verify.model_points == b.verify.model_points;
}

std::shared_ptr<const Engine> MakeEngine(const DaemonSettings& s, Models models) {
  auto e = std::make_shared<Engine>();
  e->recognition = s.recognition;
  e->fovea = s.fovea;
  e->saliency = s.saliency;
  e->saccade_fallback = s.attention.fallback == LostFallback::kSaccade;
  e->predict_max_horizon_s = s.attention.predict ? s.attention.predict_max_horizon_s : 0.0f;
  e->models = std::move(models);
  return e;
}

// Latencies in 0.1 ms bins up to 2 s (beyond: the last bin): percentiles in constant memory
// over a status period or a whole run.
class LatencyHistogram {
 public:
  void Add(double ms) {
    const auto bin = static_cast<std::size_t>(std::max(0.0, ms) * 10);
    ++bins_[std::min(bin, bins_.size() - 1)];
    ++count_;
    max_ms_ = std::max(max_ms_, ms);
  }
  double Percentile(double q) const {
    if (count_ == 0) return 0;
    const auto rank = static_cast<std::int64_t>(q * (count_ - 1));
    std::int64_t seen = 0;
    for (std::size_t i = 0; i < bins_.size(); ++i) {
      seen += bins_[i];
      if (seen > rank) return (i + 0.5) / 10;
    }
    return bins_.size() / 10.0;
  }
  /// The period's report, then empty for the next period.
  LatencyReport TakeReport(const std::string& name) {
    LatencyReport r;
    r.name = name;
    r.samples = static_cast<int>(count_);
    r.p50_ms = static_cast<float>(Percentile(0.5));
    r.p90_ms = static_cast<float>(Percentile(0.9));
    r.p99_ms = static_cast<float>(Percentile(0.99));
    r.max_ms = static_cast<float>(max_ms_);
    *this = LatencyHistogram();
    return r;
  }

 private:
  std::vector<std::int64_t> bins_ = std::vector<std::int64_t>(20000, 0);
  std::int64_t count_ = 0;
  double max_ms_ = 0;
};

double Ms(std::int64_t from_ns, std::int64_t to_ns) { return (to_ns - from_ns) * 1e-6; }

// One frame's trip through the pipeline.
struct Job {
  Frame frame;
  Fixation used;  // the fixation the frame was foveated with
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();
  bool foveated = true;
  std::vector<InstanceReport> instances;
  std::vector<Eigen::Vector3f> salient;
  double recognize_ms = 0, attention_ms = 0;
  Fixation next;  // attention's fixation after this frame
};

// How far an instance's model centroid is from where the true pose puts it. The synthetic
// Kinect's models are cut in the object's own frame, so the true pose applies to them.
float TruthError(const InstanceReport& i, const GroundTruth& truth) {
  const Eigen::Vector3f in_model = Eigen::Isometry3f(i.camera_from_model).inverse() * i.centroid_m;
  return (i.centroid_m - truth.target_pose * in_model).norm();
}

// The human line of `service.summary: line`: mode, fovea, and the error to the truth when the
// frame has one.
std::string SummaryLine(const Fixation& next, const std::vector<InstanceReport>& instances,
                        const std::optional<GroundTruth>& truth) {
  char line[160];
  const Eigen::Vector3f& p = next.fovea_m;
  const int n = std::snprintf(line, sizeof line, "%-9s fovea (%+.2f, %+.2f, %+.2f) m  G %.2f m",
                              ModeName(next.mode), p.x(), p.y(), p.z(), next.growth_m);
  if (!truth || n <= 0 || n >= static_cast<int>(sizeof line)) return line;
  float best = -1;
  for (const InstanceReport& i : instances) {
    const float d = TruthError(i, *truth);
    if (best < 0 || d < best) best = d;
  }
  if (truth->visible_fraction < 0.2f)
    std::snprintf(line + n, sizeof line - n, "  target hidden");
  else if (best < 0)
    std::snprintf(line + n, sizeof line - n, "  target not found");
  else
    std::snprintf(line + n, sizeof line - n, "  error %.1f cm", best * 100);
  return line;
}

FixationReport ToReport(const Fixation& f, std::int64_t capture_utime) {
  FixationReport r;
  r.capture_utime = capture_utime;
  r.seq = f.frame_seq;
  r.fovea_m = f.fovea_m;
  r.velocity_mps = f.velocity_mps;
  r.growth_m = f.growth_m;
  r.mode = static_cast<int>(f.mode);
  r.target = f.target;
  r.model = f.model;
  r.num_targets = f.num_targets;
  r.reason = f.reason;
  return r;
}

}  // namespace

struct Tracker::State {
  DaemonSettings settings;  // as started; Reload compares against it
  std::unique_ptr<FrameSource> source;
  std::unique_ptr<Bus> bus;
  Heartbeat heartbeat;
  std::int64_t started_ns = SteadyNowNs();

  std::mutex engine_mutex;
  std::shared_ptr<const Engine> engine;  // guarded by engine_mutex

  std::mutex attention_mutex;
  std::optional<Attention> attention;  // guarded by attention_mutex
  Fixation current;                    // the fixation new frames are foveated with
  std::optional<Command> pending;      // the latest SET_FOVEA or RESET, applied in order

  std::mutex run_mutex;
  std::condition_variable run_cv;
  bool paused = false;    // guarded by run_mutex
  bool stopping = false;  // guarded by run_mutex

  // Written by the serial stages, read by the status thread.
  std::mutex stats_mutex;
  LatencyHistogram recognize, attend, publish, capture_to_publish;  // this status period
  LatencyHistogram run_recognize, run_capture_to_publish;           // the whole run
  std::int64_t processed = 0;
  int lag_max = 0;
  AttentionMode mode = AttentionMode::kSearching;
  std::string last_summary;  // the newest frame's fovea and error, for the summary line
  std::atomic<std::int64_t> progress{0};
  std::atomic<bool> colour_checked{false};  // the first frame's colour against the models'

  std::shared_ptr<const Engine> CurrentEngine() {
    std::lock_guard<std::mutex> lock(engine_mutex);
    return engine;
  }
  bool OnCommand(const Command& c, std::string* why);
  void Recognize(Job* job);
  void Attend(Job* job);
  void Publish(Job* job);
  /// Publishes (and, with `service.summary: line` and not `final`, prints) the status; returns it.
  StatusReport PublishStatus(double period_s, std::int64_t* last_processed, bool final);
};

bool Tracker::State::OnCommand(const Command& c, std::string* why) {
  switch (c.kind) {
    case Command::Kind::kSetFovea:
    case Command::Kind::kReset: {
      std::lock_guard<std::mutex> lock(attention_mutex);
      pending = c;
      break;
    }
    case Command::Kind::kPause:
    case Command::Kind::kResume: {
      std::lock_guard<std::mutex> lock(run_mutex);
      paused = c.kind == Command::Kind::kPause;
      run_cv.notify_all();
      break;
    }
    case Command::Kind::kSwitchModel: {
      const auto old = CurrentEngine();
      std::optional<Models> models = DescribeModels({c.model}, old->recognition, why);
      if (!models) return false;
      auto next = std::make_shared<Engine>(*old);
      next->models = std::move(*models);
      {
        std::lock_guard<std::mutex> lock(engine_mutex);
        engine = next;
      }
      Command reset;
      reset.kind = Command::Kind::kReset;
      std::lock_guard<std::mutex> lock(attention_mutex);
      pending = reset;  // the old model's targets mean nothing to the new one
      Log(LogLevel::kInfo, "switched the model to '" + c.model + "'");
      break;
    }
  }
  Log(LogLevel::kDebug, "command accepted");
  return true;
}

void Tracker::State::Recognize(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  {
    std::lock_guard<std::mutex> lock(attention_mutex);
    job->used = current;
  }
  const std::shared_ptr<const Engine> engine = CurrentEngine();
  const Engine& e = *engine;
  const double t = job->frame.capture_utime * 1e-6;
  SceneQuery q;
  q.foveated = job->used.mode != AttentionMode::kFullScan;
  q.fovea_m = job->used.FoveaAt(t, e.predict_max_horizon_s);
  q.fovea = e.fovea;
  q.fovea.growth_m = Eigen::Vector3f::Constant(job->used.growth_m);
  q.intrinsics = job->frame.intrinsics;
  job->foveated = q.foveated;
  job->fovea_m = q.fovea_m;
  // Verification compares colour only when both sides have it: say once when they differ.
  if (!colour_checked.exchange(true) && !HasColour(*job->frame.cloud))
    for (const auto& model : e.models)
      if (model->description.verification().coloured)
        Log(LogLevel::kWarning, "model '" + model->name +
                                    "' has colour but the frames do not: verification runs on "
                                    "geometry alone (docs/RESULTS.md measures both)");
  // Nested parallelism runs in the pipeline's own arena.
  const ParallelFor parallel = TbbParallelFor();
  for (std::size_t m = 0; m < e.models.size(); ++m) {
    std::string error;
    const RecognitionResult r = saccade::Recognize(e.models[m]->description, *job->frame.cloud, q,
                                                   e.recognition, parallel, &error);
    if (!error.empty())
      Log(LogLevel::kDebug, "frame " + std::to_string(job->frame.sequence) + ": " + error);
    for (const Detection& d : r.instances) {
      InstanceReport i;
      i.model = static_cast<int>(m);
      i.model_name = e.models[m]->name;
      i.camera_from_model = d.model_to_scene;
      i.centroid_m = d.centroid_m;
      i.votes = d.votes;
      i.confidence = d.confidence;
      i.fitness = d.fitness;
      i.coverage = d.coverage;
      i.colour_agreement = d.colour_agreement;
      job->instances.push_back(std::move(i));
    }
  }
  // Only a search can end in a saccade; a tracking frame need not look for salient regions.
  if (e.saccade_fallback && job->used.mode == AttentionMode::kSearching)
    job->salient = SalientRegions(*job->frame.cloud, e.saliency);
  job->recognize_ms = Ms(t0, SteadyNowNs());
}

void Tracker::State::Attend(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  std::vector<Sighting> sightings;
  for (const InstanceReport& i : job->instances) sightings.push_back({i.centroid_m, i.model});
  std::lock_guard<std::mutex> lock(attention_mutex);
  Fixation f = attention->Update(static_cast<std::int64_t>(job->frame.sequence),
                                 job->frame.capture_utime * 1e-6, sightings, job->salient);
  if (pending) {  // a command overrides what this frame would have done
    if (pending->kind == Command::Kind::kSetFovea)
      attention->Reset(pending->fovea_m, "command");
    else
      attention->Reset(settings.initial_fovea_m, "reset");
    pending.reset();
    f = attention->current();
  }
  current = f;
  job->next = f;
  job->attention_ms = Ms(t0, SteadyNowNs());
}

void Tracker::State::Publish(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  FrameReport frame;
  frame.capture_utime = job->frame.capture_utime;
  frame.seq = static_cast<std::int64_t>(job->frame.sequence);
  frame.foveated = job->foveated;
  frame.fovea_m = job->fovea_m;
  frame.growth_m = job->used.growth_m;
  frame.fixation_seq = job->used.frame_seq;
  frame.recognize_ms = static_cast<float>(job->recognize_ms);
  frame.instances = std::move(job->instances);  // the last stage: nothing reads them after
  if (LogEnabled(LogLevel::kDebug)) {
    std::string votes;
    for (const InstanceReport& i : frame.instances) votes += " " + std::to_string(i.votes);
    Log(LogLevel::kDebug, "frame " + std::to_string(frame.seq) + ": " +
                              std::to_string(frame.instances.size()) + " instance(s), votes" +
                              votes + "; " + job->next.reason);
  }
  if (!bus->Publish(frame, ToReport(job->next, job->frame.capture_utime)))
    Log(LogLevel::kWarning, "frame " + std::to_string(frame.seq) + ": LCM did not send it");
  const std::int64_t t1 = SteadyNowNs();
  const std::string summary =
      settings.summary == "line" ? SummaryLine(job->next, frame.instances, job->frame.truth) : "";

  std::lock_guard<std::mutex> lock(stats_mutex);
  recognize.Add(job->recognize_ms);
  attend.Add(job->attention_ms);
  publish.Add(Ms(t0, t1));
  capture_to_publish.Add(Ms(job->frame.arrival_steady_ns, t1));
  run_recognize.Add(job->recognize_ms);
  run_capture_to_publish.Add(Ms(job->frame.arrival_steady_ns, t1));
  ++processed;
  if (job->used.frame_seq >= 0)
    lag_max = std::max<int>(lag_max, static_cast<int>(frame.seq - job->used.frame_seq));
  mode = job->next.mode;
  if (!summary.empty()) last_summary = summary;
  ++progress;
}

StatusReport Tracker::State::PublishStatus(double period_s, std::int64_t* last_processed,
                                           bool final) {
  const SourceStats source_stats = source->Stats();
  StatusReport s;
  s.uptime_s = Ms(started_ns, SteadyNowNs()) / 1000;
  s.source = settings.source;
  s.source_state = source_stats.state;
  s.frames_in = static_cast<std::int64_t>(source_stats.produced);
  s.frames_dropped = static_cast<std::int64_t>(source_stats.dropped);
  s.source_reconnects = static_cast<std::int64_t>(source_stats.reconnects);
  s.commands_accepted = bus->AcceptedCommands();
  s.commands_rejected = bus->RejectedCommands();
  {
    std::lock_guard<std::mutex> lock(run_mutex);
    s.paused = paused;
  }
  std::string summary;
  {
    std::lock_guard<std::mutex> lock(stats_mutex);
    s.frames_processed = processed;
    s.fps = static_cast<float>((processed - *last_processed) / period_s);
    *last_processed = processed;
    s.fixation_lag_max = lag_max;
    lag_max = 0;
    s.mode = static_cast<int>(mode);
    s.stages = {recognize.TakeReport("recognize"), attend.TakeReport("attention"),
                publish.TakeReport("publish"), capture_to_publish.TakeReport("capture_to_publish")};
    summary = last_summary;
  }
  if (!bus->PublishStatus(s)) Log(LogLevel::kWarning, "status: LCM did not send it");
  if (settings.summary == "line" && !final) {
    std::printf("%6.1f s  %5.1f fps  drops %-4lld %s\n", s.uptime_s, s.fps,
                static_cast<long long>(s.frames_dropped), summary.c_str());
    std::fflush(stdout);
  }
  return s;
}

Tracker::Tracker(std::unique_ptr<State> state) : state_(std::move(state)) {}
Tracker::~Tracker() = default;

std::unique_ptr<Tracker> Tracker::Create(const DaemonSettings& settings, Heartbeat heartbeat,
                                         std::string* error) {
  auto state = std::make_unique<State>();
  state->settings = settings;
  state->heartbeat = std::move(heartbeat);
  std::optional<Models> models = DescribeModels(settings.models, settings.recognition, error);
  if (!models) return nullptr;
  state->engine = MakeEngine(settings, std::move(*models));
  state->attention.emplace(settings.attention, settings.initial_fovea_m);
  state->current = state->attention->current();
  State* s = state.get();
  state->bus = OpenLcmBus(
      settings.bus, [s](const Command& c, std::string* why) { return s->OnCommand(c, why); },
      error);
  if (!state->bus) return nullptr;
  state->source = OpenSource(settings.source, error);
  if (!state->source) return nullptr;
  return std::unique_ptr<Tracker>(new Tracker(std::move(state)));
}

void Tracker::Stop() {
  {
    std::lock_guard<std::mutex> lock(state_->run_mutex);
    state_->stopping = true;
  }
  state_->run_cv.notify_all();
  state_->source->Stop();
}

bool Tracker::Reload(const DaemonSettings& next, std::string* error) {
  State& s = *state_;
  const auto old = s.CurrentEngine();
  Models models = old->models;
  if (next.models != s.settings.models || !SameModelRadii(next.recognition, old->recognition)) {
    std::optional<Models> described = DescribeModels(next.models, next.recognition, error);
    if (!described) return false;
    models = std::move(*described);
  }
  {
    std::lock_guard<std::mutex> lock(s.engine_mutex);
    s.engine = MakeEngine(next, std::move(models));
  }
  {
    std::lock_guard<std::mutex> lock(s.attention_mutex);
    s.attention->SetOptions(next.attention);
  }
  std::vector<std::string> kept;
  const DaemonSettings& was = s.settings;
  if (next.source != was.source) kept.push_back("source");
  if (next.bus.url != was.bus.url || next.bus.channel_prefix != was.bus.channel_prefix ||
      next.bus.commands != was.bus.commands || next.bus.to_robot_frame != was.bus.to_robot_frame ||
      !next.bus.robot_from_camera.isApprox(was.bus.robot_from_camera))
    kept.push_back("lcm/robot_frame");
  if (next.frames_in_flight != was.frames_in_flight || next.threads != was.threads)
    kept.push_back("pipeline");
  for (const std::string& k : kept)
    Log(LogLevel::kWarning, "reload: '" + k + "' changed; it takes effect at the next restart");
  std::lock_guard<std::mutex> lock(s.attention_mutex);  // Attend reads initial_fovea_m
  s.settings.recognition = next.recognition;
  s.settings.fovea = next.fovea;
  s.settings.attention = next.attention;
  s.settings.saliency = next.saliency;
  s.settings.models = next.models;
  s.settings.initial_fovea_m = next.initial_fovea_m;
  return true;
}

bool Tracker::Run(std::string* error) {
  State& s = *state_;
  Log(LogLevel::kInfo, "source " + s.source->Describe() + "; LCM " + s.bus->Describe() + "; " +
                           std::to_string(s.settings.frames_in_flight) + " frames in flight");
  // The status thread: a heartbeat at the status period, and the watchdog's pulse.
  std::mutex status_mutex;
  std::condition_variable status_cv;
  bool status_done = false;
  std::int64_t last_processed = 0;
  std::thread status([&] {
    std::int64_t seen = s.progress;
    std::unique_lock<std::mutex> lock(status_mutex);
    const auto period = std::chrono::duration<double>(s.settings.status_period_s);
    while (!status_cv.wait_for(lock, period, [&] { return status_done; })) {
      const StatusReport status =
          s.PublishStatus(s.settings.status_period_s, &last_processed, false);
      const std::int64_t now = s.progress;
      const bool waiting = status.paused || status.source_state.rfind("reconnecting", 0) == 0;
      if (s.heartbeat) s.heartbeat(now != seen || waiting);
      seen = now;
    }
  });

  std::string source_error;
  const int threads =
      s.settings.threads > 0 ? s.settings.threads : tbb::info::default_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_pipeline(static_cast<std::size_t>(s.settings.frames_in_flight),
                           tbb::make_filter<void, std::shared_ptr<Job>>(
                               tbb::filter_mode::serial_in_order,
                               [&](tbb::flow_control& fc) -> std::shared_ptr<Job> {
                                 {
                                   std::unique_lock<std::mutex> lock(s.run_mutex);
                                   s.run_cv.wait(lock, [&] { return !s.paused || s.stopping; });
                                   if (s.stopping) {
                                     fc.stop();
                                     return nullptr;
                                   }
                                 }
                                 auto job = std::make_shared<Job>();
                                 std::string err;
                                 const FrameSource::Status st = s.source->Next(&job->frame, &err);
                                 if (st != FrameSource::Status::kFrame) {
                                   if (st == FrameSource::Status::kError) source_error = err;
                                   fc.stop();
                                   return nullptr;
                                 }
                                 if (job->frame.arrival_steady_ns == 0)
                                   job->frame.arrival_steady_ns = SteadyNowNs();
                                 return job;
                               }) &
                               tbb::make_filter<std::shared_ptr<Job>, std::shared_ptr<Job>>(
                                   tbb::filter_mode::parallel,
                                   [&](std::shared_ptr<Job> job) {
                                     s.Recognize(job.get());
                                     return job;
                                   }) &
                               tbb::make_filter<std::shared_ptr<Job>, std::shared_ptr<Job>>(
                                   tbb::filter_mode::serial_in_order,
                                   [&](std::shared_ptr<Job> job) {
                                     s.Attend(job.get());
                                     return job;
                                   }) &
                               tbb::make_filter<std::shared_ptr<Job>, void>(
                                   tbb::filter_mode::serial_in_order,
                                   [&](std::shared_ptr<Job> job) { s.Publish(job.get()); }));
  });
  {
    std::lock_guard<std::mutex> lock(status_mutex);
    status_done = true;
  }
  status_cv.notify_all();
  status.join();
  // A last status with the final counts, so a finite run's log ends with them (its fps is
  // the run's mean).
  last_processed = 0;
  s.PublishStatus(std::max(1e-3, Ms(s.started_ns, SteadyNowNs()) / 1000), &last_processed, true);
  {
    // The run in one line: what a benchmark of the daemon reads.
    const SourceStats stats = s.source->Stats();
    std::lock_guard<std::mutex> lock(s.stats_mutex);
    const double seconds = Ms(s.started_ns, SteadyNowNs()) / 1000;
    const double in = static_cast<double>(std::max<std::uint64_t>(stats.produced, 1));
    char line[256];
    std::snprintf(line, sizeof line,
                  "run: %lld frames processed in %.1f s (%.1f fps), %llu of %llu dropped "
                  "(%.2f%%); recognize p50 %.1f ms p99 %.1f ms; capture-to-publish p50 %.1f ms "
                  "p99 %.1f ms",
                  static_cast<long long>(s.processed), seconds, s.processed / seconds,
                  static_cast<unsigned long long>(stats.dropped),
                  static_cast<unsigned long long>(stats.produced), 100.0 * stats.dropped / in,
                  s.run_recognize.Percentile(0.5), s.run_recognize.Percentile(0.99),
                  s.run_capture_to_publish.Percentile(0.5),
                  s.run_capture_to_publish.Percentile(0.99));
    Log(LogLevel::kInfo, line);
  }
  if (!source_error.empty()) {
    *error = "source " + s.settings.source + ": " + source_error;
    return false;
  }
  return true;
}

}  // namespace saccade
