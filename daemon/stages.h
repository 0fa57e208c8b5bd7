// The tracker's stages (daemon/tracker.cc runs them in a pipeline). Each owns its state and
// the lock that guards it: Recognize may run for several frames at once, Track, Attend and
// Publish run serially in frame order, and the status thread reads Publish's figures.
#pragma once

#include "attention/attention.h"
#include "attention/tracks.h"
#include "core/candidates.h"
#include "core/frame.h"
#include "core/library.h"
#include "core/recognition.h"
#include "core/saliency.h"
#include "daemon/latency_histogram.h"
#include "daemon/settings.h"
#include "io/base/log.h"
#include "io/lcm/bus.h"
#include "io/sources/frame_source.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// A described model under the name (its spec) it is published with.
struct NamedModel {
  std::string name;
  ModelDescription description;
  ModelSignature signature;                            // what whole-frame candidates look for
  Eigen::Vector3f extent_m = Eigen::Vector3f::Zero();  // its size along its own axes
};
using Models = std::vector<std::shared_ptr<const NamedModel>>;

/// What recognition and tracking run with, swapped whole (a reload, a model switch): a frame
/// keeps the configuration it started with.
struct StageConfig {
  RecognitionOptions recognition;
  FoveaOptions fovea;
  SaliencyOptions saliency;
  TrackingOptions tracking;
  bool saccade_fallback = false;   // look for salient regions while searching
  bool search_candidates = false;  // propose whole-frame candidates while searching
  /// A given fovea lands on the best candidate this near it, in the frame it is given for
  /// (AttentionOptions::land_on_candidate_m and land_stay_m; 0: it stays where given).
  float land_on_candidate_m = 0, land_stay_m = 0;
  CandidateOptions candidates;
  float predict_max_horizon_s = 0;  // the predictor's lead (0: off)
  PreviewOptions preview;           // PREFIX_PREVIEW (off by default)
  Models models;
  /// The models searched together (core/library.h): one description of a frame per radius.
  /// It points into `models`: set both with RecognizeStage::SetModels.
  std::shared_ptr<const Library> library;
};

/// One frame's trip through the stages.
struct Job {
  Frame frame;
  Fixation used;          // the fixation the frame was foveated with
  Looks plan;             // the further places the frame may look at (Attention::PlanLooks)
  bool recognize = true;  // false: the tracks hold and no re-check is due, tracking alone
  /// >= 0: recognition sweeps the whole frame (unfoveated, this window of the keypoint budget)
  /// for the models no track holds, instead of looking at the fovea (TrackSet::SweepPhase).
  int sweep_phase = -1;
  /// The models recognition runs for, by index (TrackSet::ModelsToRecognize); empty: all.
  std::vector<bool> models;
  /// A re-check: recognition looks here (camera frame, G = 0) instead of at the fovea
  /// (TrackSet::RecheckAt).
  std::optional<Eigen::Vector3f> recheck_at;
  std::shared_ptr<const StageConfig> config;  // what the frame runs with (set by Recognize)
  FrameDetections detections;  // what recognition found; after Track, what is published
  /// Where a search looks next, best first: the frame's candidates (attention.search:
  /// candidates) or the coarse level's salient regions (the saccade fallback).
  std::vector<Eigen::Vector3f> salient;
  /// Where recognition landed a given fovea (Fixation::lands) before looking: attention is
  /// told (Attention::Landed), so the landing is not made again a frame later.
  std::optional<Eigen::Vector3f> landed_m;
  /// Where recognition looked after its first look (Looks::Take): attention counts each as a
  /// candidate visit (Attention::Looked).
  std::vector<Eigen::Vector3f> looks;
  /// A live frame's further looks must end by then (steady clock, ns) for the pipeline to keep
  /// pace with the source (pipeline.looks_keep_pace, LooksUntilNs). 0: no limit.
  std::int64_t looks_until_ns = 0;
  double track_ms = 0, attention_ms = 0;
  std::string track_events;  // what changed in the tracks, for the fixation's reason
  Fixation next;             // attention's fixation after this frame
};

/// How often a live source's frames arrive: the median of the last intervals between the
/// frames the pipeline took, each divided by the frames the source made in it (their
/// sequence numbers): frames dropped between two do not stretch the period, which would give
/// the looks more time and drop more.
class ArrivalPeriod {
 public:
  void Add(std::int64_t arrival_ns, std::uint64_t sequence);
  /// 0 until two frames have arrived.
  std::int64_t ns() const;

 private:
  static constexpr std::size_t kIntervals = 15;
  std::int64_t last_ns_ = 0;
  std::uint64_t last_sequence_ = 0;
  std::vector<std::int64_t> intervals_;  // the last kIntervals, oldest first
};

/// When a live frame that arrived at `arrival_ns` must end its further looks to keep pace
/// with the source: before the frame `frames_in_flight` after it arrives (the pipeline then
/// has room for it: no frame waits, none is overwritten), less a quarter period for tracking
/// and publishing. A frame that waited (its predecessor ran late) has less time; a late frame
/// takes no further look, nor does one that arrives before the period is known (the first: its
/// looks left over are the next frame's, which knows the pace).
std::int64_t LooksUntilNs(std::int64_t arrival_ns, std::int64_t period_ns, int frames_in_flight);

/// Loads and describes each model spec (a PCD file, or synthetic:target); several are put on
/// the library's radius grid (RecognitionOptions::library_radius_ratio). nullopt with one line
/// in `error` naming the model that failed.
std::optional<Models> DescribeModels(const std::vector<std::string>& specs,
                                     const RecognitionOptions& options, std::string* error);

/// Foveates each frame at the fixation it was given and recognizes every model in it (unless
/// the job says the tracks hold).
class RecognizeStage {
 public:
  using Config = StageConfig;
  static std::shared_ptr<const Config> MakeConfig(const DaemonSettings& settings, Models models);
  /// Replaces c's models and the library over them (the library points into the models: they
  /// change together, never one alone).
  static void SetModels(Config* c, Models models);

  explicit RecognizeStage(std::shared_ptr<const Config> config) : config_(std::move(config)) {}
  std::shared_ptr<const Config> config() const;
  void SetConfig(std::shared_ptr<const Config> config);
  /// Sets job->config; fills job->detections (and job->salient) from job->frame and
  /// job->used, or only their header when !job->recognize. Thread-safe.
  void Process(Job* job);

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const Config> config_;     // guarded by mutex_
  std::atomic<bool> colour_checked_{false};  // the first frame's colour against the models'
};

/// Frame-to-frame tracking: every held track refined on the frame, recognition's instances
/// taken by the tracks; job->detections.instances become the tracks' (attention/tracks.h).
class TrackStage {
 public:
  explicit TrackStage(const TrackingOptions& options) : tracks_(options) {}
  /// Whether the next frame needs recognition, and what for: job->recognize, job->sweep_phase,
  /// job->recheck_at and job->models. Thread-safe.
  void PlanRecognition(Job* job) const;
  /// Serial, in frame order.
  void Process(Job* job);
  /// Forgets every track after the frame in progress (a model switch, RESET). Thread-safe.
  void Clear();

 private:
  mutable std::mutex mutex_;
  TrackSet tracks_;     // guarded by mutex_
  Models models_;       // guarded by mutex_: the models the tracks were made with
  bool clear_ = false;  // guarded by mutex_: forget the tracks before the next frame
};

/// The attention loop, and the commands that move it.
class AttendStage {
 public:
  AttendStage(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m);
  /// The fixation new frames are foveated with. Thread-safe.
  Fixation Current() const;
  /// That fixation, and the further looks a frame foveated with it may take. Thread-safe.
  void Plan(Job* job) const;
  /// Digests the job's detections into job->next (a pending command overrides it). Serial, in
  /// frame order.
  void Process(Job* job);
  /// SET_FOVEA or RESET: applied after the next frame instead of what it would have done.
  void Command(const Command& command);
  /// New options and initial fovea (a reload); targets are kept.
  void SetOptions(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m);

 private:
  mutable std::mutex mutex_;
  Attention attention_;                      // guarded by mutex_
  Fixation current_;                         // guarded by mutex_
  std::optional<saccade::Command> pending_;  // guarded by mutex_: the latest SET_FOVEA or RESET
  Eigen::Vector3f initial_fovea_m_;          // guarded by mutex_: where RESET looks
};

/// Sends each frame's detections and fixation, and keeps the figures the status reports.
class PublishStage {
 public:
  /// `bus` outlives the stage; with `summary_line`, a human line per status period.
  PublishStage(Bus* bus, bool summary_line) : bus_(bus), summary_line_(summary_line) {}
  /// Serial, in frame order: the job's detections leave with it, and, with the job's
  /// config->preview on and a preview due (at most preview.rate_hz a second), its preview.
  void Process(Job* job);

  /// The figures of the period since the last call (stages, fps, fixation lag, mode, frames
  /// processed) into `status`, and the newest summary line; with `whole_run` the fps is over
  /// every frame published (`period_s` then being the run's length). Thread-safe.
  void TakePeriod(double period_s, bool whole_run, StatusReport* status, std::string* summary);
  /// Frames published so far; grows while frames flow (the watchdog's pulse). Thread-safe.
  std::int64_t Progress() const { return progress_; }
  /// The whole run in one line (frames, fps, drops, recognize and capture-to-publish p50/p99).
  std::string RunLine(double seconds, const SourceStats& source) const;
  /// With ground truth (synthetic frames, recordings that carry it): "target within 2 cm in N
  /// of M frames it was visible in, median error E cm"; empty without truth. Thread-safe.
  std::string TruthLine() const;
  static constexpr float kTrackedWithinM = 0.02f;

 private:
  Bus* const bus_;
  const bool summary_line_;
  /// The job's preview to the bus; the time it took (ms), or -1 when none was due.
  double SendPreview(const Job& job);

  LogLimiter send_failure_log_{1};  // a network that refuses every send: one line a second
  LogLimiter preview_failure_log_{1};
  std::int64_t last_preview_ns_ = 0;  // Process's own (serial)
  mutable std::mutex mutex_;
  LatencyHistogram recognize_, track_, attend_, publish_, capture_to_publish_;  // this period
  LatencyHistogram preview_;  // this period's previews (reported while previews are made)
  LatencyHistogram run_recognize_, run_track_, run_capture_to_publish_;  // the whole run
  std::int64_t recognized_ = 0;  // frames recognition ran on (the others were tracked alone)
  std::int64_t processed_ = 0, last_processed_ = 0;
  std::int64_t unsent_ = 0;  // frames whose detections or fixation LCM did not send
  int lag_max_ = 0;
  AttentionMode mode_ = AttentionMode::kSearching;
  std::string last_summary_;  // the newest frame's fovea and error, for the summary line
  // Frames with truth in which the target was visible, those with an instance within
  // kTrackedWithinM of it, and the best instance's error in 1 mm bins (the last: 1 m or more,
  // or not found).
  std::int64_t truth_visible_ = 0, truth_tracked_ = 0;
  std::vector<std::int64_t> truth_error_mm_ = std::vector<std::int64_t>(1001, 0);
  std::atomic<std::int64_t> progress_{0};
};

}  // namespace saccade
