#include "daemon/stages.h"

#include "daemon/attention_command.h"

#include "core/fail.h"
#include "core/foveation.h"
#include "daemon/tbb_parallel.h"
#include "io/base/log.h"
#include "io/formats/cloud_io.h"
#include "io/sources/frame_source.h"
#include "io/sources/model_source.h"

#include <algorithm>
#include <cstdio>

namespace saccade {
namespace {

double Ms(std::int64_t from_ns, std::int64_t to_ns) { return (to_ns - from_ns) * 1e-6; }

// How far an instance's model centroid is from where the true pose puts it. The synthetic
// Kinect's models are cut in the object's own frame, so the true pose applies to them.
float TruthError(const Detection& d, const GroundTruth& truth) {
  const Eigen::Vector3f in_model = Eigen::Isometry3f(d.model_to_scene).inverse() * d.centroid_m;
  return (d.centroid_m - truth.target_pose * in_model).norm();
}

// A target with less of itself in view than this is "hidden": not counted as trackable.
constexpr float kVisibleFraction = 0.2f;

// The best instance's distance to the truth, or -1 when none was found.
float BestTruthError(const std::vector<Detection>& instances, const GroundTruth& truth) {
  float best = -1;
  for (const Detection& d : instances) {
    const float e = TruthError(d, truth);
    if (best < 0 || e < best) best = e;
  }
  return best;
}

// The human line of `service.summary: line`: mode, fovea, and each instance the frame holds (its
// model's short name, track and state, centroid), then the error to the truth when the frame
// carries one.
std::string SummaryLine(const Fixation& next, const FrameDetections& frame,
                        const std::optional<GroundTruth>& truth, float best) {
  char part[160];
  const Eigen::Vector3f& p = next.fovea_m;
  std::snprintf(part, sizeof part, "%-9s fovea (%+.2f, %+.2f, %+.2f) m  G %.2f m",
                ModeName(next.mode), p.x(), p.y(), p.z(), next.growth_m);
  std::string line = part;
  for (const Detection& d : frame.instances) {
    const std::string name = d.model >= 0 && std::size_t(d.model) < frame.models.size()
                                 ? ModelShortName(frame.models[std::size_t(d.model)])
                                 : "?";
    const Eigen::Vector3f& c = d.centroid_m;
    std::snprintf(part, sizeof part, "  | %.40s #%d %s (%+.2f, %+.2f, %+.2f)", name.c_str(),
                  d.track_id, TrackStateName(d.track_state), c.x(), c.y(), c.z());
    line += part;
  }
  if (!truth) return line;
  if (truth->visible_fraction < kVisibleFraction)
    line += "  target hidden";
  else if (best < 0)
    line += "  target not found";
  else
    std::snprintf(part, sizeof part, "  error %.1f cm", best * 100), line += part;
  return line;
}

// Every model's candidates in one list, best score first.
std::vector<Eigen::Vector3f> MergedCandidates(const Cloud& cloud, const CameraIntrinsics& k,
                                              const Models& models, const CandidateOptions& o) {
  std::vector<Candidate> all;
  for (const auto& m : models) {
    if (m->signature.radius_m <= 0) continue;
    const std::vector<Candidate> c = ProposeCandidates(cloud, k, m->signature, o);
    all.insert(all.end(), c.begin(), c.end());
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  std::vector<Eigen::Vector3f> out;
  for (const Candidate& c : all) out.push_back(c.centre_m);
  return out;
}

// True when a frame foveated at `used` lands it on a candidate first: the fovea was given and
// not landed yet, and the search visits candidates.
bool LandsNow(const StageConfig& c, const Fixation& used) {
  return used.lands && used.mode == AttentionMode::kSearching && c.search_candidates &&
         c.land_on_candidate_m > 0;
}

}  // namespace

std::optional<Models> DescribeModels(const std::vector<std::string>& specs,
                                     const RecognitionOptions& options, std::string* error) {
  Models models;
  for (const std::string& spec : specs) {
    std::optional<std::vector<Cloud>> views = LoadModelViews(spec, error);
    if (!views) return std::nullopt;
    std::string why;
    const float radius_ratio = specs.size() > 1 ? options.library_radius_ratio : 1.0f;
    std::optional<ModelDescription> d = DescribeModel(*views, options, &why, radius_ratio);
    if (!d) {
      Fail(error, "model '" + spec + "': " + why);
      return std::nullopt;
    }
    const ModelSignature signature = SignModel(*d);
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
    for (const PointT& p : d->cloud())
      if (FinitePoint(p))
        lo = lo.cwiseMin(p.getVector3fMap()), hi = hi.cwiseMax(p.getVector3fMap());
    const Eigen::Vector3f extent = (hi - lo).cwiseMax(0.0f);
    models.push_back(
        std::make_shared<const NamedModel>(NamedModel{spec, std::move(*d), signature, extent}));
  }
  return models;
}

std::shared_ptr<const RecognizeStage::Config> RecognizeStage::MakeConfig(const DaemonSettings& s,
                                                                         Models models) {
  auto c = std::make_shared<Config>();
  c->recognition = s.recognition;
  c->fovea = s.fovea;
  c->saliency = s.saliency;
  c->tracking = s.tracking;
  c->saccade_fallback = s.attention.fallback == LostFallback::kSaccade;
  c->search_candidates = s.attention.search == SearchKind::kCandidates;
  c->candidates = s.candidates;
  c->land_on_candidate_m = s.attention.land_on_candidate_m;
  c->land_stay_m = s.attention.land_stay_m;
  c->predict_max_horizon_s = s.attention.predict ? s.attention.predict_max_horizon_s : 0.0f;
  c->preview = s.preview;
  SetModels(c.get(), std::move(models));
  return c;
}

void RecognizeStage::SetModels(Config* c, Models models) {
  c->models = std::move(models);
  std::vector<const ModelDescription*> descriptions;
  for (const auto& m : c->models) descriptions.push_back(&m->description);
  c->library = std::make_shared<const Library>(std::move(descriptions), c->recognition);
}

std::shared_ptr<const RecognizeStage::Config> RecognizeStage::config() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return config_;
}

void RecognizeStage::SetConfig(std::shared_ptr<const Config> config) {
  std::lock_guard<std::mutex> lock(mutex_);
  config_ = std::move(config);
}

void RecognizeStage::Process(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  job->config = this->config();
  const Config& c = *job->config;
  const Frame& frame = job->frame;
  SceneQuery q;
  q.foveated = job->used.mode != AttentionMode::kFullScan;
  q.fovea_m = job->used.FoveaAt(frame.capture_utime * 1e-6, c.predict_max_horizon_s);
  q.fovea = c.fovea;
  q.fovea.growth_m = Eigen::Vector3f::Constant(job->used.growth_m);
  q.intrinsics = frame.intrinsics;
  q.search_phase = job->used.SearchPhase();
  if (job->sweep_phase >= 0) {  // the whole frame, one window of the budget, for lost models
    q.foveated = false;
    q.search_phase = job->sweep_phase;
  } else if (job->recheck_at) {  // at the track, G = 0, the nearest window
    q.foveated = true;
    q.fovea_m = *job->recheck_at;
    q.fovea.growth_m.setZero();
    q.search_phase = 0;
  } else if (job->recognize && LandsNow(c, job->used)) {
    // A given fovea (the initial one, a reset, a command) lands on the object near it, or a
    // guess on the frame's best candidate, in this very frame: the candidates cost about a
    // millisecond, a frame recognized where nothing is 33.
    job->salient = MergedCandidates(*frame.cloud, frame.intrinsics, c.models, c.candidates);
    job->landed_m = LandGiven(job->used, job->salient, c.land_on_candidate_m, c.land_stay_m);
    q.fovea_m = *job->landed_m;
  }
  FrameDetections& out = job->detections;
  out.seq = static_cast<std::int64_t>(frame.sequence);
  out.capture_utime = frame.capture_utime;
  out.arrival_steady_ns = frame.arrival_steady_ns;
  out.foveated = q.foveated;
  out.fovea_m = q.fovea_m;
  out.growth_m = q.fovea.growth_m.x();
  out.fixation_seq = job->used.frame_seq;
  for (const auto& model : c.models) {
    out.models.push_back(model->name);
    out.model_extents_m.push_back(model->extent_m);
  }
  if (!job->recognize) return;  // the tracks hold: recognize_ms stays 0
  // Verification compares colour only when both sides have it: say once when they differ.
  if (!colour_checked_.exchange(true) && !HasColour(*frame.cloud))
    for (const auto& model : c.models)
      if (model->description.verification().coloured)
        Log(LogLevel::kWarning, "model '" + model->name +
                                    "' has colour but the frames do not: verification runs on "
                                    "geometry alone (docs/RESULTS.md measures both)");
  // Nested parallelism runs in the pipeline's own arena.
  const ParallelFor parallel = TbbParallelFor();
  // A re-check (tracks held, some due) looks at the track only: its own keypoint budget.
  RecognitionOptions options = c.recognition;
  if (job->recheck_at && c.tracking.recheck_max_keypoints > 0)
    options.max_scene_keypoints = c.tracking.recheck_max_keypoints;
  // The mask is of the models the job was planned with: a reload since then runs them all.
  const bool masked = job->models.size() == c.models.size();
  std::string error;
  const std::int64_t first_look_ns = SteadyNowNs();
  LibraryResult r = RecognizeLibrary(*c.library, *frame.cloud, q, options,
                                     masked ? job->models : std::vector<bool>{}, parallel, &error);
  const std::int64_t first_look_took_ns = SteadyNowNs() - first_look_ns;
  if (!error.empty()) Log(LogLevel::kDebug, "frame " + std::to_string(out.seq) + ": " + error);
  out.instances = std::move(r.instances);
  // Only a search looks elsewhere: at every model's candidates, best first, or at the salient
  // regions of the saccade fallback.
  if (job->used.mode == AttentionMode::kSearching && !job->landed_m) {
    if (c.search_candidates)
      job->salient = MergedCandidates(*frame.cloud, frame.intrinsics, c.models, c.candidates);
    else if (c.saccade_fallback)
      job->salient = SalientRegions(*frame.cloud, c.saliency);
  }
  // A search may look at its next candidates in this frame too, until one holds an instance
  // confident enough to start a track (attention.looks_per_frame, Attention::PlanLooks), and
  // on a live source while a look as long as the longest yet would end in time.
  if (job->plan.left > 0 && c.search_candidates && q.foveated && job->sweep_phase < 0 &&
      !job->recheck_at) {
    Looks plan = job->plan;
    if (c.tracking.enabled) plan.enough_confidence = c.tracking.min_track_confidence;
    error.clear();
    std::int64_t longest_look_ns = first_look_took_ns;
    const auto in_time = [&] {
      return job->looks_until_ns == 0 || SteadyNowNs() + longest_look_ns <= job->looks_until_ns;
    };
    job->looks = plan.Take(
        q.fovea_m, job->salient, &out.instances,
        [&](const Eigen::Vector3f& place, std::vector<Detection>* found) {
          const std::int64_t started_ns = SteadyNowNs();
          SceneQuery look = q;
          look.fovea_m = place;
          look.search_phase = 0;  // the window nearest the candidate
          LibraryResult seen =
              RecognizeLibrary(*c.library, *frame.cloud, look, options,
                               masked ? job->models : std::vector<bool>{}, parallel, &error);
          for (Detection& d : seen.instances) found->push_back(std::move(d));
          longest_look_ns = std::max(longest_look_ns, SteadyNowNs() - started_ns);
        },
        in_time);
    if (!job->looks.empty() && plan.moves_fovea) out.fovea_m = job->looks.back();
    if (!error.empty()) Log(LogLevel::kDebug, "frame " + std::to_string(out.seq) + ": " + error);
  }
  out.recognize_ms = static_cast<float>(Ms(t0, SteadyNowNs()));
}

void TrackStage::PlanRecognition(Job* job) const {
  std::lock_guard<std::mutex> lock(mutex_);
  job->recognize = clear_ || tracks_.NeedsRecognition();
  job->sweep_phase = job->recognize && !clear_ ? tracks_.SweepPhase() : -1;
  job->models.clear();
  job->recheck_at.reset();
  if (!job->recognize || clear_) return;
  job->models = tracks_.ModelsToRecognize();
  if (job->sweep_phase < 0) job->recheck_at = tracks_.RecheckAt();
}

void TrackStage::Clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  clear_ = true;
}

void TrackStage::Process(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  const StageConfig& c = *job->config;
  std::lock_guard<std::mutex> lock(mutex_);
  // Other models (a switch, a reload that described them again): the tracks mean nothing now.
  if (clear_ || c.models != models_) {
    if (tracks_.size() > 0) job->track_events = "tracks cleared";
    tracks_.Clear();
    models_ = c.models;
    clear_ = false;
  }
  tracks_.SetOptions(c.tracking);
  std::vector<TrackModel> models;
  for (const auto& m : c.models)
    models.push_back(TrackModel{&m->description.verification(), m->description.centroid()});
  TrackFrame f;
  f.seq = static_cast<std::int64_t>(job->frame.sequence);
  f.time_s = job->frame.capture_utime * 1e-6;
  f.cloud = job->frame.cloud.get();
  f.intrinsics = job->frame.intrinsics;
  f.recognized = job->recognize;
  f.sweep = job->sweep_phase >= 0;
  f.recognized_models = job->models;
  f.searched_centre_m = job->detections.fovea_m;
  // Attention follows what no track holds: the best instance of its search (Attention's
  // "tentative"), which may start a track below tracking.min_track_confidence.
  f.attended = FollowsTentative(job->used);
  // Recognition confirms what lies in the fovea's finest box (grown by G); outside it the
  // coarse levels may miss an object that is there.
  f.searched_half_m = job->detections.foveated
                          ? 0.5f * c.fovea.inner_size_m.maxCoeff() + job->detections.growth_m
                          : -1.0f;
  job->detections.instances =
      tracks_.Update(f, models, job->detections.instances, &job->track_events);
  job->track_ms = Ms(t0, SteadyNowNs());
  job->detections.track_ms = static_cast<float>(job->track_ms);
}

AttendStage::AttendStage(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m)
    : attention_(options, initial_fovea_m),
      current_(attention_.current()),
      initial_fovea_m_(initial_fovea_m) {}

Fixation AttendStage::Current() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return current_;
}

void AttendStage::Plan(Job* job) const {
  std::lock_guard<std::mutex> lock(mutex_);
  job->used = current_;
  job->plan = attention_.PlanLooks();
}

void AttendStage::Process(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  // Attention follows what is seen: held tracks, or recognition's instances without tracking.
  const bool tracking = job->config && job->config->tracking.enabled;
  std::vector<Detection> seen;
  for (const Detection& d : job->detections.instances) {
    if (!Actionable(d.track_state, tracking)) continue;
    seen.push_back(d);
    // A held track passed the acquisition bar when it started (tracking.min_track_confidence):
    // attention follows it whatever its score now, and the tracks, not attention, challenge it.
    if (tracking) seen.back().confidence = -1;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  // A search from nothing (no target known, or the one attention chose without a track): the
  // instances the tracks declined (below tracking.min_track_confidence) are what it remembers,
  // to follow the best once its candidates are visited. A lost track's search does not follow
  // them: a look-alike is the usual instance while the object hides.
  const Fixation& now = attention_.current();
  const bool from_nothing = now.target < 0 || FollowsTentative(now);
  if (tracking && seen.empty() && from_nothing)
    for (const Detection& d : job->detections.instances)
      if (d.track_state == TrackState::kNone) seen.push_back(d);
  if (job->landed_m) attention_.Landed(job->used.fovea_m, *job->landed_m);
  if (!job->looks.empty())
    attention_.Looked(job->used.frame_seq, job->landed_m.value_or(job->used.fovea_m), job->looks);
  Fixation f = attention_.Update(static_cast<std::int64_t>(job->frame.sequence),
                                 job->frame.capture_utime * 1e-6, seen, job->salient);
  if (pending_) {  // a command overrides what this frame would have done
    ApplyFixationCommand(*pending_, initial_fovea_m_, &attention_);
    pending_.reset();
    f = attention_.current();
  }
  if (!job->track_events.empty()) f.reason += ": " + job->track_events;
  current_ = f;
  job->next = f;
  job->attention_ms = Ms(t0, SteadyNowNs());
}

void AttendStage::Command(const saccade::Command& command) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_ = command;
}

void AttendStage::SetOptions(const AttentionOptions& options,
                             const Eigen::Vector3f& initial_fovea_m) {
  std::lock_guard<std::mutex> lock(mutex_);
  attention_.SetOptions(options);
  initial_fovea_m_ = initial_fovea_m;
}

void PublishStage::Process(Job* job) {
  const std::int64_t t0 = SteadyNowNs();
  const FrameDetections& frame = job->detections;
  if (LogEnabled(LogLevel::kDebug)) {
    std::string votes;
    for (const Detection& d : frame.instances) votes += " " + std::to_string(d.votes);
    Log(LogLevel::kDebug, "frame " + std::to_string(frame.seq) + ": " +
                              std::to_string(frame.instances.size()) + " instance(s), votes" +
                              votes + "; " + job->next.reason);
  }
  std::int64_t unsaid = 0;
  const bool sent = bus_->Publish(frame, job->next);
  if (!sent && send_failure_log_.Allow(&unsaid))
    Log(LogLevel::kWarning,
        "frame " + std::to_string(frame.seq) + ": LCM did not send it" +
            (unsaid > 0 ? " (nor " + std::to_string(unsaid) + " frames before it, unlogged)"
                        : std::string()));
  const std::int64_t t1 = SteadyNowNs();
  const double preview_ms = SendPreview(*job);
  // The truth's error once, for the summary line and the run's tally.
  const auto& truth = job->frame.truth;
  const float best = truth ? BestTruthError(frame.instances, *truth) : -1;
  const bool visible = truth && truth->visible_fraction >= kVisibleFraction;
  const std::string summary = summary_line_ ? SummaryLine(job->next, frame, truth, best) : "";

  std::lock_guard<std::mutex> lock(mutex_);
  recognize_.Add(frame.recognize_ms);
  track_.Add(job->track_ms);
  attend_.Add(job->attention_ms);
  publish_.Add(Ms(t0, t1));
  if (preview_ms >= 0) preview_.Add(preview_ms);
  capture_to_publish_.Add(Ms(job->frame.arrival_steady_ns, t1));
  if (job->recognize) {
    run_recognize_.Add(frame.recognize_ms);
    ++recognized_;
  }
  run_track_.Add(job->track_ms);
  run_capture_to_publish_.Add(Ms(job->frame.arrival_steady_ns, t1));
  ++processed_;
  if (!sent) ++unsent_;
  if (job->used.frame_seq >= 0)
    lag_max_ = std::max<int>(lag_max_, static_cast<int>(frame.seq - job->used.frame_seq));
  mode_ = job->next.mode;
  if (!summary.empty()) last_summary_ = summary;
  if (visible) {
    ++truth_visible_;
    if (best >= 0 && best <= kTrackedWithinM) ++truth_tracked_;
    const auto last = static_cast<long>(truth_error_mm_.size()) - 1;
    ++truth_error_mm_[static_cast<std::size_t>(
        best < 0 ? last : std::min<long>(last, std::lround(best * 1000)))];
  }
  ++progress_;
}

double PublishStage::SendPreview(const Job& job) {
  const PreviewOptions& options = job.config ? job.config->preview : PreviewOptions{};
  const std::int64_t now = SteadyNowNs();
  if (!options.enabled || !job.frame.cloud ||
      (last_preview_ns_ != 0 &&
       now - last_preview_ns_ < static_cast<std::int64_t>(1e9 / options.rate_hz)))
    return -1;
  last_preview_ns_ = now;
  const Cloud& scene = *job.frame.cloud;
  const FrameDetections& d = job.detections;
  FoveaGeometry geometry;
  if (const auto bounds = BoundingBox(scene)) {
    FoveaOptions fovea = job.config->fovea;
    fovea.growth_m = Eigen::Vector3f::Constant(d.growth_m);
    geometry = ComputeFoveaGeometry(fovea, *bounds, d.fovea_m);
  }
  PreviewModels models;
  for (const auto& m : job.config->models) models.push_back(m ? &m->description.cloud() : nullptr);
  Preview preview =
      MakePreview(scene, job.frame.intrinsics, geometry, d.instances, models, options);
  preview.seq = d.seq;
  preview.fovea_m = d.fovea_m;
  preview.growth_m = d.growth_m;
  // The truth as an instance's centroid would be at it: the target (the first model) at the
  // true pose, the point TruthError measures from.
  if (job.frame.truth && !job.config->models.empty() && job.config->models[0]) {
    preview.has_truth = true;
    preview.truth_centroid_m =
        job.frame.truth->target_pose * job.config->models[0]->description.centroid();
  }
  std::string why;
  std::int64_t unsaid = 0;
  if (!bus_->PublishPreview(preview, job.frame.arrival_steady_ns, options, &why) &&
      preview_failure_log_.Allow(&unsaid))
    Log(LogLevel::kWarning,
        "frame " + std::to_string(d.seq) + ": " + why +
            (unsaid > 0 ? " (and " + std::to_string(unsaid) + " more, unlogged)" : std::string()));
  return Ms(now, SteadyNowNs());
}

void PublishStage::TakePeriod(double period_s, bool whole_run, StatusReport* s,
                              std::string* summary) {
  std::lock_guard<std::mutex> lock(mutex_);
  s->frames_processed = processed_;
  s->frames_unsent = unsent_;
  s->fps = static_cast<float>((processed_ - (whole_run ? 0 : last_processed_)) / period_s);
  last_processed_ = processed_;
  s->fixation_lag_max = lag_max_;
  lag_max_ = 0;
  s->mode = mode_;
  s->stages = {recognize_.TakeReport("recognize"), track_.TakeReport("track"),
               attend_.TakeReport("attention"), publish_.TakeReport("publish"),
               capture_to_publish_.TakeReport("capture_to_publish")};
  if (preview_.count() > 0) s->stages.push_back(preview_.TakeReport("preview"));
  *summary = last_summary_;
}

std::string PublishStage::TruthLine() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (truth_visible_ == 0) return "";
  std::int64_t below = 0;
  std::size_t median_mm = 0;
  while (2 * (below + truth_error_mm_[median_mm]) < truth_visible_ + 1 &&
         median_mm + 1 < truth_error_mm_.size())
    below += truth_error_mm_[median_mm++];
  char line[160];
  std::snprintf(line, sizeof line,
                "target within %.0f cm in %lld of %lld frames it was visible in, median error %s",
                kTrackedWithinM * 100, static_cast<long long>(truth_tracked_),
                static_cast<long long>(truth_visible_),
                median_mm + 1 == truth_error_mm_.size() ? "over 1 m (or not found)"
                                                        : (std::to_string(median_mm / 10) + "." +
                                                           std::to_string(median_mm % 10) + " cm")
                                                              .c_str());
  return line;
}

std::string PublishStage::RunLine(double seconds, const SourceStats& source) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const double in = static_cast<double>(std::max<std::uint64_t>(source.produced, 1));
  char line[320];
  std::snprintf(line, sizeof line,
                "run: %lld frames processed in %.1f s (%.1f fps), %llu of %llu dropped "
                "(%.2f%%); recognized %lld, recognize p50 %.1f ms p99 %.1f ms; track p50 %.2f ms "
                "p99 %.2f ms; capture-to-publish p50 %.1f ms p99 %.1f ms",
                static_cast<long long>(processed_), seconds, processed_ / seconds,
                static_cast<unsigned long long>(source.dropped),
                static_cast<unsigned long long>(source.produced), 100.0 * source.dropped / in,
                static_cast<long long>(recognized_), run_recognize_.Percentile(0.5),
                run_recognize_.Percentile(0.99), run_track_.Percentile(0.5),
                run_track_.Percentile(0.99), run_capture_to_publish_.Percentile(0.5),
                run_capture_to_publish_.Percentile(0.99));
  std::string run = line;
  if (source.skipped > 0)
    run += "; " + std::to_string(source.skipped) + " unusable frame(s) of the source skipped";
  if (unsent_ > 0)
    run += "; LCM did not send " + std::to_string(unsent_) + " of the frames processed";
  return run;
}

void ArrivalPeriod::Add(std::int64_t arrival_ns, std::uint64_t sequence) {
  if (last_ns_ > 0 && arrival_ns > last_ns_ && sequence > last_sequence_) {
    if (intervals_.size() == kIntervals) intervals_.erase(intervals_.begin());
    intervals_.push_back((arrival_ns - last_ns_) /
                         static_cast<std::int64_t>(sequence - last_sequence_));
  }
  last_ns_ = arrival_ns;
  last_sequence_ = sequence;
}

std::int64_t ArrivalPeriod::ns() const {
  if (intervals_.empty()) return 0;
  std::vector<std::int64_t> sorted = intervals_;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return sorted[sorted.size() / 2];
}

std::int64_t LooksUntilNs(std::int64_t arrival_ns, std::int64_t period_ns, int frames_in_flight) {
  if (period_ns <= 0) return arrival_ns;  // the pace not known yet: no further look
  return arrival_ns + frames_in_flight * period_ns - period_ns / 4;
}

}  // namespace saccade
