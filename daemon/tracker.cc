#include "daemon/tracker.h"

#include "core/fail.h"
#include "daemon/serial_worker.h"
#include "daemon/stages.h"
#include "io/base/log.h"

#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <thread>

namespace saccade {
namespace {

double Seconds(std::int64_t from_ns, std::int64_t to_ns) { return (to_ns - from_ns) * 1e-9; }

// The settings a running tracker cannot change, by the name the log gives them.
std::vector<std::string> NeedRestart(const DaemonSettings& was, const DaemonSettings& next) {
  std::vector<std::string> kept;
  if (next.source != was.source) kept.push_back("source");
  if (next.bus != was.bus) kept.push_back("lcm/robot_frame");
  if (next.pipeline != was.pipeline) kept.push_back("pipeline");
  if (next.ros2 != was.ros2) kept.push_back("ros2");
  if (next.log != was.log) kept.push_back("log");
  return kept;
}

// Where SWITCH_MODEL may load models from: lcm.model_dirs, or the configured models' folders.
std::vector<std::string> ModelDirs(const DaemonSettings& s) {
  if (!s.bus.model_dirs.empty()) return s.bus.model_dirs;
  std::vector<std::string> dirs;
  for (const auto& m : s.models) {
    if (m.find(':') != std::string::npos && m.find('/') > m.find(':')) continue;  // a spec
    const auto slash = m.rfind('/');
    dirs.push_back(slash == std::string::npos ? "." : slash == 0 ? "/" : m.substr(0, slash));
  }
  return dirs;
}

}  // namespace

struct Tracker::Impl {
  Impl(const DaemonSettings& s, Models models, std::unique_ptr<FrameSource> source_,
       std::unique_ptr<Bus> bus_, Heartbeat heartbeat_)
      : settings(s),
        source(std::move(source_)),
        bus(std::move(bus_)),
        heartbeat(std::move(heartbeat_)),
        recognize(RecognizeStage::MakeConfig(s, std::move(models))),
        track(s.tracking),
        attend(s.attention, s.initial_fovea_m),
        publish(bus.get(), s.service.summary == ServiceOptions::Summary::kLine) {}

  // The control thread is stopped first, while the bus it replies through is alive; then the
  // bus, whose receiver may still post (and is refused); the stages after.
  ~Impl() {
    closing = true;
    control.Stop();
    bus.reset();
  }

  void OnCommand(const Command& c, const CommandReply& reply);
  void SwitchModel(const std::string& spec, const CommandReply& reply);
  void ApplyReload(const DaemonSettings& next, const Done& done);
  /// Publishes (and, with `service.summary: line` and not `final`, prints) the status.
  StatusReport PublishStatus(double period_s, bool final);
  /// Paused, or a camera being waited for (at start or after a loss): alive, not stuck.
  bool Waiting();
  std::shared_ptr<Job> NextJob(std::string* source_error);
  void RunPipeline(std::string* source_error);

  const DaemonSettings settings;  // as started: what a reload may not change is checked here
  std::unique_ptr<FrameSource> source;
  std::unique_ptr<Bus> bus;
  const Heartbeat heartbeat;
  const std::int64_t started_ns = SteadyNowNs();
  std::int64_t datagrams_dropped = 0;  // by the kernel, as of the last status (its thread's)
  ArrivalPeriod arrivals;              // a live source's frames (the pipeline's first stage's)

  RecognizeStage recognize;
  TrackStage track;
  AttendStage attend;
  PublishStage publish;

  std::mutex run_mutex;
  std::condition_variable run_cv;
  bool paused = false;    // guarded by run_mutex
  bool stopping = false;  // guarded by run_mutex

  std::mutex models_mutex;  // serializes model changes (switches and reloads) on the control thread
  std::vector<std::string> model_specs;  // guarded by models_mutex: what the models were made from
  // Where SWITCH_MODEL may load from: lcm.model_dirs, or the configured models' folders.
  const std::vector<std::string> model_dirs = ModelDirs(settings);

  // At most one SWITCH_MODEL waits for the control thread: a later one takes its place (the last
  // wins) and the one replaced is refused, so a flood of switches costs one description, not
  // one each, and stopping never waits behind a queue of them.
  std::mutex switch_mutex;
  std::optional<std::pair<std::string, CommandReply>> pending_switch;  // guarded by switch_mutex
  std::atomic<bool> closing{false};  // set by Stop: a switch not yet begun is refused
  void RunPendingSwitch();

  SerialWorker control;  // model switches and reloads; the last member, so stopped first
};

void Tracker::Impl::OnCommand(const Command& c, const CommandReply& reply) {
  switch (c.kind) {
    case Command::Kind::kSetFovea:
    case Command::Kind::kReset:
      attend.Command(c);
      track.Clear();  // or the tracks would pull the fovea straight back
      break;
    case Command::Kind::kPause:
    case Command::Kind::kResume: {
      std::lock_guard<std::mutex> lock(run_mutex);
      paused = c.kind == Command::Kind::kPause;
      run_cv.notify_all();
      break;
    }
    case Command::Kind::kSwitchModel: {
      std::string why;
      if (!CommandModelAllowed(c.model, model_dirs, &why)) return reply(false, why);
      // Describing a model takes seconds: not on the bus's thread.
      std::optional<CommandReply> replaced;
      bool post = false;
      {
        std::lock_guard<std::mutex> lock(switch_mutex);
        if (pending_switch)
          replaced = pending_switch->second;
        else
          post = true;
        pending_switch.emplace(c.model, reply);
      }
      if (replaced) (*replaced)(false, "replaced by a later SWITCH_MODEL before it was loaded");
      if (post && !control.Post([this] { RunPendingSwitch(); })) RunPendingSwitch();
      return;
    }
  }
  Log(LogLevel::kDebug, "command accepted");
  reply(true, "");
}

void Tracker::Impl::RunPendingSwitch() {
  std::optional<std::pair<std::string, CommandReply>> next;
  {
    std::lock_guard<std::mutex> lock(switch_mutex);
    next.swap(pending_switch);
  }
  if (!next) return;
  if (closing) return next->second(false, "the tracker is stopping");
  SwitchModel(next->first, next->second);
}

void Tracker::Impl::SwitchModel(const std::string& spec, const CommandReply& reply) {
  std::lock_guard<std::mutex> lock(models_mutex);
  const auto old = recognize.config();
  std::string why;
  std::optional<Models> models = DescribeModels({spec}, old->recognition, &why);
  if (!models) return reply(false, why);
  auto next = std::make_shared<RecognizeStage::Config>(*old);
  RecognizeStage::SetModels(next.get(), std::move(*models));
  recognize.SetConfig(std::move(next));
  model_specs = {spec};
  Command reset;  // the old model's targets mean nothing to the new one
  reset.kind = Command::Kind::kReset;
  attend.Command(reset);
  Log(LogLevel::kInfo, "switched the model to '" + spec + "'");
  reply(true, "");
}

void Tracker::Impl::ApplyReload(const DaemonSettings& next, const Done& done) {
  std::lock_guard<std::mutex> lock(models_mutex);
  const auto old = recognize.config();
  Models models = old->models;
  // A model's description depends on the recognition options (its radii, the match index,
  // verification's sample): any change describes the models again.
  if (next.models != model_specs || next.recognition != old->recognition) {
    std::string why;
    std::optional<Models> described = DescribeModels(next.models, next.recognition, &why);
    if (!described) return done(false, why);
    models = std::move(*described);
    model_specs = next.models;
  }
  recognize.SetConfig(RecognizeStage::MakeConfig(next, std::move(models)));
  attend.SetOptions(next.attention, next.initial_fovea_m);
  for (const std::string& k : NeedRestart(settings, next))
    Log(LogLevel::kWarning, "reload: '" + k + "' changed; it takes effect at the next restart");
  done(true, "");
}

StatusReport Tracker::Impl::PublishStatus(double period_s, bool final) {
  const SourceStats source_stats = source->Stats();
  StatusReport s;
  s.uptime_s = Seconds(started_ns, SteadyNowNs());
  s.source = settings.source.spec;
  s.source_state = source_stats.state;
  s.frames_in = static_cast<std::int64_t>(source_stats.produced);
  s.frames_dropped = static_cast<std::int64_t>(source_stats.dropped);
  s.frames_skipped = static_cast<std::int64_t>(source_stats.skipped);
  s.source_reconnects = static_cast<std::int64_t>(source_stats.reconnects);
  s.commands_accepted = bus->AcceptedCommands();
  s.commands_rejected = bus->RejectedCommands();
  s.lcm_datagrams_dropped = bus->DroppedDatagrams();
  if (s.lcm_datagrams_dropped > datagrams_dropped)
    Log(LogLevel::kWarning,
        "LCM: the kernel dropped " + std::to_string(s.lcm_datagrams_dropped - datagrams_dropped) +
            " datagram(s) before saccaded could read them (a full receive buffer: a message "
            "larger than net.core.rmem_max, or a flood); a command among them was lost");
  datagrams_dropped = s.lcm_datagrams_dropped;
  {
    std::lock_guard<std::mutex> lock(run_mutex);
    s.paused = paused;
  }
  std::string summary;
  publish.TakePeriod(period_s, final, &s, &summary);
  if (!bus->PublishStatus(s)) Log(LogLevel::kWarning, "status: LCM did not send it");
  if (settings.service.summary == ServiceOptions::Summary::kLine && !final) {
    std::printf("%6.1f s  %5.1f fps  drops %-4lld %s\n", s.uptime_s, s.fps,
                static_cast<long long>(s.frames_dropped), summary.c_str());
    std::fflush(stdout);
  }
  return s;
}

bool Tracker::Impl::Waiting() {
  const std::string state = source->Stats().state;
  std::lock_guard<std::mutex> lock(run_mutex);
  return paused || state.rfind("reconnecting", 0) == 0 || state.rfind("waiting for device", 0) == 0;
}

// The pipeline's first stage: the next frame, or nullptr when paused into a stop, stopped, or
// the source ended or failed.
std::shared_ptr<Job> Tracker::Impl::NextJob(std::string* source_error) {
  {
    std::unique_lock<std::mutex> lock(run_mutex);
    run_cv.wait(lock, [&] { return !paused || stopping; });
    if (stopping) return nullptr;
  }
  auto job = std::make_shared<Job>();
  std::string err;
  const FrameSource::Status st = source->Next(&job->frame, &err);
  if (st != FrameSource::Status::kFrame) {
    if (st == FrameSource::Status::kError) *source_error = err;
    return nullptr;
  }
  if (job->frame.arrival_steady_ns == 0) job->frame.arrival_steady_ns = SteadyNowNs();
  if (source->Live()) {
    arrivals.Add(job->frame.arrival_steady_ns, job->frame.sequence);
    if (settings.pipeline.looks_keep_pace)
      job->looks_until_ns = LooksUntilNs(job->frame.arrival_steady_ns, arrivals.ns(),
                                         settings.pipeline.frames_in_flight);
  }
  attend.Plan(job.get());
  track.PlanRecognition(job.get());
  return job;
}

void Tracker::Impl::RunPipeline(std::string* source_error) {
  using JobPtr = std::shared_ptr<Job>;
  const int threads =
      settings.pipeline.threads > 0 ? settings.pipeline.threads : tbb::info::default_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_pipeline(
        static_cast<std::size_t>(settings.pipeline.frames_in_flight),
        tbb::make_filter<void, JobPtr>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control&
                                                                                  fc) {
          JobPtr job = NextJob(source_error);
          if (!job) fc.stop();
          return job;
        }) & tbb::make_filter<JobPtr, JobPtr>(tbb::filter_mode::parallel, [&](JobPtr job) {
          recognize.Process(job.get());
          return job;
        }) & tbb::make_filter<JobPtr, JobPtr>(tbb::filter_mode::serial_in_order, [&](JobPtr job) {
          track.Process(job.get());
          return job;
        }) & tbb::make_filter<JobPtr, JobPtr>(tbb::filter_mode::serial_in_order, [&](JobPtr job) {
          attend.Process(job.get());
          return job;
        }) & tbb::make_filter<JobPtr, void>(tbb::filter_mode::serial_in_order, [&](JobPtr job) {
          publish.Process(job.get());
        }));
  });
}

Tracker::Tracker(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {
  Impl* s = impl_.get();
  s->model_specs = s->settings.models;
  s->bus->Subscribe([s](const Command& c, CommandReply reply) { s->OnCommand(c, reply); });
}
Tracker::~Tracker() = default;

std::unique_ptr<Tracker> Tracker::Create(const DaemonSettings& settings,
                                         std::unique_ptr<FrameSource> source,
                                         std::unique_ptr<Bus> bus, Heartbeat heartbeat,
                                         std::string* error) {
  std::optional<Models> models = DescribeModels(settings.models, settings.recognition, error);
  if (!models) return nullptr;
  return std::unique_ptr<Tracker>(new Tracker(std::make_unique<Impl>(
      settings, std::move(*models), std::move(source), std::move(bus), std::move(heartbeat))));
}

std::unique_ptr<Tracker> Tracker::Open(const DaemonSettings& settings, Heartbeat heartbeat,
                                       std::string* error) {
  std::optional<Models> models = DescribeModels(settings.models, settings.recognition, error);
  if (!models) return nullptr;
  std::vector<std::unique_ptr<MessageMirror>> mirrors;
  if (settings.ros2.enabled) {
    mirrors.push_back(OpenRos2Mirror(settings.ros2, settings.bus.robot, error));
    if (!mirrors.back()) return nullptr;
  }
  if (!settings.log.mcap.empty()) {
    mirrors.push_back(OpenMcapMirror(settings.log.mcap,
                                     static_cast<std::uint64_t>(settings.log.mcap_max_mb * 1e6),
                                     settings.ros2, error));
    if (!mirrors.back()) return nullptr;
  }
  std::unique_ptr<Bus> bus = OpenLcmBus(settings.bus, error, std::move(mirrors));
  if (!bus) return nullptr;
  std::unique_ptr<FrameSource> source =
      OpenSource(settings.source.spec, error, settings.source.wait_at_start_s);
  if (!source) return nullptr;
  return std::unique_ptr<Tracker>(new Tracker(std::make_unique<Impl>(
      settings, std::move(*models), std::move(source), std::move(bus), std::move(heartbeat))));
}

void Tracker::Process(Frame frame) {
  Job job;
  job.frame = std::move(frame);
  if (job.frame.arrival_steady_ns == 0) job.frame.arrival_steady_ns = SteadyNowNs();
  impl_->attend.Plan(&job);
  impl_->track.PlanRecognition(&job);
  impl_->recognize.Process(&job);
  impl_->track.Process(&job);
  impl_->attend.Process(&job);
  impl_->publish.Process(&job);
}

void Tracker::Stop() {
  {
    std::lock_guard<std::mutex> lock(impl_->run_mutex);
    impl_->stopping = true;
  }
  impl_->closing = true;
  impl_->run_cv.notify_all();
  impl_->source->Stop();
}

void Tracker::Reload(const DaemonSettings& next, Done done) {
  Impl* s = impl_.get();
  if (!s->control.Post([s, next, done] { s->ApplyReload(next, done); }))
    done(false, "the tracker is stopping");
}

void Tracker::WaitForControl() { impl_->control.Flush(); }

std::string Tracker::ClosingLine() const {
  const std::string truth = impl_->publish.TruthLine();
  if (truth.empty() || !impl_->source) return "stopped";
  const SourceStats stats = impl_->source->Stats();
  return "stopped: " + truth + "; " + std::to_string(stats.dropped) + " of " +
         std::to_string(stats.produced) + " frames dropped at the source's rate";
}

bool Tracker::Run(std::string* error) {
  Impl& s = *impl_;
  if (!s.source) return Fail(error, "no frame source: this tracker is driven by Process()");
  Log(LogLevel::kInfo, "source " + s.source->Describe() + "; LCM " + s.bus->Describe() + "; " +
                           std::to_string(s.settings.pipeline.frames_in_flight) +
                           " frames in flight");
  // The status thread: a status at the status period, and a heartbeat (the watchdog's pulse)
  // at least every kHeartbeatPeriod.
  std::mutex status_mutex;
  std::condition_variable status_cv;
  bool status_done = false;
  std::thread status([&] {
    using Clock = std::chrono::steady_clock;
    std::int64_t seen = s.publish.Progress();
    std::unique_lock<std::mutex> lock(status_mutex);
    const auto period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(s.settings.service.status_period_s));
    const auto beat = std::min(period, std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(kHeartbeatPeriod)));
    auto next_status = Clock::now() + period;
    while (!status_cv.wait_for(lock, beat, [&] { return status_done; })) {
      std::optional<StatusReport> status;
      if (Clock::now() >= next_status) {
        status = s.PublishStatus(s.settings.service.status_period_s, false);
        next_status = std::max(next_status + period, Clock::now());
      }
      const std::int64_t now = s.publish.Progress();
      if (s.heartbeat) s.heartbeat(now != seen || s.Waiting(), status ? &*status : nullptr);
      seen = now;
    }
  });

  std::string source_error;
  s.RunPipeline(&source_error);
  {
    std::lock_guard<std::mutex> lock(status_mutex);
    status_done = true;
  }
  status_cv.notify_all();
  status.join();
  // A last status with the final counts, so a finite run's log ends with them (its fps is
  // the run's mean); then the run in one line: what a benchmark of the daemon reads.
  const double seconds = std::max(1e-3, Seconds(s.started_ns, SteadyNowNs()));
  s.PublishStatus(seconds, true);
  std::string run = s.publish.RunLine(seconds, s.source->Stats());
  const std::int64_t accepted = s.bus->AcceptedCommands(), rejected = s.bus->RejectedCommands();
  if (accepted + rejected > 0)
    run += "; commands: " + std::to_string(accepted) + " acted on, " + std::to_string(rejected) +
           " refused";
  if (s.datagrams_dropped > 0)
    run += "; LCM datagrams dropped by the kernel: " + std::to_string(s.datagrams_dropped);
  Log(LogLevel::kInfo, run);
  if (!source_error.empty()) {
    return Fail(error, "source " + s.settings.source.spec + ": " + source_error);
  }
  return true;
}

}  // namespace saccade
