// saccade bench-track: the tracker on one sequence with exact truth, as saccaded would run it
// at the sensor's rate on this machine. Frames arrive every 1/rate seconds; the tracker takes
// the newest one whenever it is free (a latest-frame mailbox, as the live sources) and the
// frames it had no time for are dropped. Each frame's cost is its measured processing time, so
// the figures are this machine's, and a frame's rendering is not counted. Per sequence: the
// share of visible frames tracked within the tolerance, frames from (re)appearance to
// re-acquisition, frames held on a wrong place, and the costs; the last line is one JSON object.
// Several models (--model A,B,...) are scored each against its own truth: the sequence's
// target, then its others.
#include "core/eval/pose_scoring.h"
#include "core/fail.h"
#include "core/recognition.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/cli/progress.h"
#include "daemon/latency_histogram.h"
#include "daemon/settings.h"
#include "daemon/tbb_parallel.h"
#include "daemon/tracker.h"
#include "io/base/json.h"
#include "io/base/log.h"
#include "io/formats/cloud_io.h"
#include "io/formats/output_file.h"
#include "io/formats/truth_file.h"
#include "io/lcm/memory_bus.h"
#include "io/sources/frame_source.h"
#include "io/sources/model_source.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <ostream>
#include <utility>

namespace saccade {
namespace {

struct Tally {
  int frames = 0, processed = 0, visible = 0, within = 0, wrong = 0, recognized = 0;
  int reappearances = 0, never_reacquired = 0, max_reacquire = 0;
  // Each time an object goes out of sight: processed frames it was still held, the most.
  int disappearances = 0, max_held_after_gone = 0;
  LatencyHistogram track_ms, recognize_ms, frame_ms;
  /// Frames that came while every track was held (none lost or searching): the cost of
  /// tracking with its re-checks, without the searches.
  LatencyHistogram tracking_frame_ms;
};

}  // namespace

// The defaults, in the help and in the run alike.
constexpr double kRateHz = 30, kToleranceCm = 1, kToleranceDeg = 2, kWrongCm = 5;

int RunBenchTrack(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade bench-track",
            "Runs the tracker on a sequence with truth at the sensor's rate (frames it has no "
            "time for are dropped): the share of visible frames within tolerance, frames to "
            "re-acquire, frames on a wrong place, costs. The last line is one JSON object.");
  args.Value("source", "SPEC",
             "the frames and their truth (see saccade record --help for "
             "SPEC) (required)")
      .Value("model", "M[,M2,...]",
             "the models, the target first; model j is scored against "
             "the frame's truth j (required)")
      .Value("config", "FILE.yaml", "saccaded's settings (configs/saccaded.yaml)")
      .Value("name", "NAME", "the sequence's name in the report (default: the source)")
      .Value("rate", "HZ", "the sensor's rate, frames a second" + Args::Default(kRateHz))
      .Value("tolerance-cm", "C",
             "a frame is tracked within C centimetres" + Args::Default(kToleranceCm))
      .Value("tolerance-deg", "D", "... and D degrees of the truth" + Args::Default(kToleranceDeg))
      .Value("wrong-cm", "W",
             "a detection over W centimetres off is on a wrong place" + Args::Default(kWrongCm))
      .Value("frames-out", "F.jsonl",
             "write one JSON line a frame (each object: visible, within, wrong, the error and, "
             "when an instance was scored, its position at_m and the truth's truth_at_m; the "
             "truth's centroid_m; where recognition looked, looked_at_m)")
      .Value("truth", "FILE.csv",
             "the target's pose per frame (frame,T00..T33, the camera frame), for a source "
             "that carries none (a recording by others); frames without a row are not scored")
      .Value("model-from-frame", "N",
             "with --truth: the model was cut from frame N and kept in that frame's camera "
             "frame (saccade segment), so its truth at frame i is the table's pose at i times "
             "the inverse of frame N's")
      .Value("symmetry", "cube",
             "the target looks the same turned onto any of its frame's axes: its rotation "
             "error is the least over those turns")
      .Value("frames", "N",
             "stop after N frames (a looped source, loop=1, makes a long run of a short one)")
      .Switch("fovea-on-truth",
              "no tracker: every frame recognized alone with the fovea on the target's true "
              "centroid (recognition as a perfect attention would aim it; nothing dropped)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  if (!args.Has("source") || !args.Has("model"))
    return Usage(err, "bench-track", "--source and --model are required");
  const auto number = [&](const char* flag, double fallback) -> std::optional<double> {
    if (!args.Has(flag)) return fallback;
    const auto v = Args::ParseNumber(args.Get(flag));
    if (!v || !(*v > 0)) return std::nullopt;
    return v;
  };
  const auto rate = number("rate", kRateHz), tol_cm = number("tolerance-cm", kToleranceCm),
             tol_deg = number("tolerance-deg", kToleranceDeg),
             wrong_cm = number("wrong-cm", kWrongCm);
  if (!rate || !tol_cm || !tol_deg || !wrong_cm)
    return Usage(err, "bench-track",
                 "--rate, --tolerance-cm, --tolerance-deg and --wrong-cm expect numbers > 0");
  if (args.Has("symmetry") && args.Get("symmetry") != "cube")
    return Usage(err, "bench-track", "--symmetry knows cube only");
  std::optional<int> max_frames;
  if (args.Has("frames")) {
    max_frames = Args::ParsePositiveInt(args.Get("frames"));
    if (!max_frames) return Usage(err, "bench-track", "--frames expects a positive integer");
  }
  std::map<int, Eigen::Isometry3f> truth_table;
  if (args.Has("truth") && !ReadPoseTable(args.Get("truth"), &truth_table, &error)) {
    err << "saccade bench-track: " << error << "\n";
    return kExitFailure;
  }
  // The turns that leave the target looking the same (the identity alone unless --symmetry),
  // about the object's own frame; and where the model's frame is in the object's.
  std::vector<Eigen::Matrix4f> turns{Eigen::Matrix4f::Identity()};
  if (args.Has("symmetry")) turns = CubeRotations();
  Eigen::Matrix4f model_in_object = Eigen::Matrix4f::Identity();
  if (args.Has("model-from-frame")) {
    const auto n = Args::ParseNumber(args.Get("model-from-frame"));
    const auto row = n ? truth_table.find(int(*n)) : truth_table.end();
    if (!args.Has("truth") || row == truth_table.end() || *n != std::floor(*n))
      return Usage(err, "bench-track", "--model-from-frame expects a frame of the --truth table");
    model_in_object = row->second.inverse().matrix();
  }
  DaemonSettings settings;
  if (args.Has("config") && !LoadDaemonSettings(args.Get("config"), &settings, &error)) {
    err << "saccade bench-track: " << error << "\n";
    return kExitFailure;
  }
  // Model j is scored against the frame's truth j: the target, then the sequence's others.
  settings.models = Args::ParseList(args.Get("model"));
  if (args.Has("truth") && settings.models.size() != 1)
    return Usage(err, "bench-track", "--truth scores one model: give one --model");
  ConfigureLog("saccade bench-track", LogLevel::kWarning);
  std::unique_ptr<FrameSource> source = OpenSource(args.Get("source"), &error);
  if (!source) {
    err << "saccade bench-track: " << error << "\n";
    return kExitFailure;
  }
  auto bus = std::make_unique<MemoryBus>();
  MemoryBus* published = bus.get();
  const bool at_truth = args.Has("fovea-on-truth");
  std::unique_ptr<Tracker> tracker =
      at_truth ? nullptr : Tracker::Create(settings, nullptr, std::move(bus), nullptr, &error);
  if (!at_truth && !tracker) {
    err << "saccade bench-track: " << error << "\n";
    return kExitFailure;
  }
  // --fovea-on-truth: the target's model described once, as the tracker would describe it.
  std::optional<ModelDescription> described;
  if (at_truth) {
    const auto views = LoadModelViews(settings.models[0], &error);
    if (views) described = DescribeModel(*views, settings.recognition, &error);
    if (!described) {
      err << "saccade bench-track: " << settings.models[0] << ": " << error << "\n";
      return kExitFailure;
    }
  }
  const ParallelFor parallel_for = MakeTbbParallelFor();
  std::vector<Eigen::Vector3f> centres;  // each model's centroid, its frame
  for (const std::string& spec : settings.models) {
    const std::optional<Cloud> model_cloud = LoadModelCloud(spec, &error);
    if (!model_cloud) {
      err << "saccade bench-track: " << error << "\n";
      return kExitFailure;
    }
    centres.push_back(FiniteCentroid(*model_cloud).value_or(Eigen::Vector3f::Zero()));
  }
  const std::size_t objects = centres.size();

  // Each frame's outcome per object; frames are taken as a latest-frame mailbox would hand
  // them over.
  struct ObjectOutcome {
    bool visible = false, good = false, wrong = false;
    double error_cm = -1, error_deg = -1;  // the held instance nearest the truth
    // That instance's pose and the model's truth (when error_cm >= 0); unaligned in a vector.
    Eigen::Matrix<float, 4, 4, Eigen::DontAlign> pose, truth;
    Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();  // the truth's centroid of the object
  };
  struct Outcome {
    bool processed = false;
    std::vector<ObjectOutcome> objects;
    std::string states, reason;
    std::optional<Eigen::Vector3f> looked_at_m;  // the fovea recognition looked at, if it ran
  };
  const auto truth_of = [](const GroundTruth& g, std::size_t j) {
    return j == 0 ? GroundTruth::Object{g.target_pose, g.centroid_m, g.visible_fraction}
                  : g.others[j - 1];
  };
  std::vector<Outcome> outcomes;
  Tally t;
  bool all_held = false;  // the last processed frame's tracks were all held
  // Recognition alone, the fovea on the target's truth: every instance it keeps counts.
  const auto recognize_at_truth = [&](const Frame& f) {
    SceneQuery query;
    query.fovea_m = f.truth->centroid_m;
    query.fovea = settings.fovea;
    query.intrinsics = f.intrinsics;
    const std::int64_t t0 = SteadyNowNs();
    FrameDetections d;
    d.instances =
        Recognize(*described, *f.cloud, query, settings.recognition, parallel_for).instances;
    d.recognize_ms = (SteadyNowNs() - t0) * 1e-6;
    for (Detection& i : d.instances) i.model = 0, i.track_state = TrackState::kNone;
    return d;
  };
  const auto process = [&](Frame f, std::size_t index) {
    const GroundTruth truth = *f.truth;
    const std::int64_t t0 = SteadyNowNs();
    FrameDetections d;
    if (at_truth) {
      d = recognize_at_truth(f);
    } else {
      tracker->Process(std::move(f));
      d = published->Frames().back().frame;
    }
    const double ms = (SteadyNowNs() - t0) * 1e-6;
    t.frame_ms.Add(ms);
    if (all_held) t.tracking_frame_ms.Add(ms);
    t.track_ms.Add(d.track_ms);
    if (d.recognize_ms > 0) {
      t.recognize_ms.Add(d.recognize_ms);
      ++t.recognized;
    }
    all_held = std::any_of(d.instances.begin(), d.instances.end(),
                           [](const Detection& i) { return i.track_id >= 0; }) &&
               std::all_of(d.instances.begin(), d.instances.end(), [](const Detection& i) {
                 return i.track_id < 0 || Actionable(i.track_state, /*tracking=*/true);
               });
    Outcome& o = outcomes[index];
    o.processed = true;
    o.reason = at_truth ? "fovea on the truth" : published->Frames().back().fixation.reason;
    if (d.recognize_ms > 0 && (at_truth || d.foveated))  // not for the whole frame
      o.looked_at_m = at_truth ? truth.centroid_m : d.fovea_m;
    for (const Detection& inst : d.instances) {
      char state[48];
      std::snprintf(state, sizeof state, "%s%s %.2f", o.states.empty() ? "" : ", ",
                    TrackStateName(inst.track_state), inst.confidence);
      o.states += state;
      if (!at_truth && !Actionable(inst.track_state, settings.tracking.enabled)) continue;
      const std::size_t j = static_cast<std::size_t>(inst.model);
      ObjectOutcome& oo = o.objects[j];
      // The truth the instance is scored against: a symmetric target's turned the nearest way,
      // so that frame-to-frame errors compare like with like.
      Eigen::Matrix4f matched = truth_of(truth, j).pose.matrix();
      const PoseError e = j == 0 ? LeastError(inst.model_to_scene, truth.target_pose.matrix(),
                                              model_in_object, centres[j], turns, &matched)
                                 : ComparePoses(inst.model_to_scene, matched, centres[j]);
      if (oo.error_cm < 0 || e.translation_m * 100 < oo.error_cm) {
        oo.error_cm = e.translation_m * 100;
        oo.error_deg = e.rotation_deg;
        oo.pose = inst.model_to_scene;
        oo.truth = matched;
      }
      if (e.translation_m * 100 <= *tol_cm && e.rotation_deg <= *tol_deg) oo.good = true;
      if (e.translation_m * 100 > *wrong_cm) oo.wrong = true;
    }
    return ms * 1e-3;
  };
  double busy_until_s = 0;  // the simulated clock: when the tracker is free again
  std::optional<std::pair<Frame, std::size_t>> pending;  // arrived while it was busy
  Frame frame;
  ProgressLine progress(err, ProgressLine::StderrIsATerminal());  // on a terminal only
  for (std::size_t i = 0; !max_frames || i < std::size_t(*max_frames); ++i) {
    progress.Show("saccade bench-track: frames", i, max_frames ? std::size_t(*max_frames) : 0);
    const FrameSource::Status st = source->Next(&frame, &error);
    if (st == FrameSource::Status::kError) {
      err << "saccade bench-track: " << error << "\n";
      return kExitFailure;
    }
    if (st != FrameSource::Status::kFrame) break;
    if (args.Has("truth")) {  // the table's row, or nothing to score this frame against
      GroundTruth g;
      const auto row = truth_table.find(int(i));
      if (row != truth_table.end()) {
        g.target_pose = row->second;
        g.centroid_m =
            (row->second.matrix() * model_in_object * centres[0].homogeneous()).head<3>();
        g.visible_fraction = 1;
      }
      frame.truth = g;
    }
    if (!frame.truth) {
      err << "saccade bench-track: " << args.Get("source") << ": frame " << i
          << " carries no truth\n";
      return kExitFailure;
    }
    if (frame.truth->others.size() + 1 < objects) {
      err << "saccade bench-track: " << args.Get("source") << ": frame " << i
          << " carries the truth of " << frame.truth->others.size() + 1 << " objects, " << objects
          << " models given\n";
      return kExitFailure;
    }
    outcomes.emplace_back();
    outcomes.back().objects.resize(objects);
    for (std::size_t j = 0; j < objects; ++j) {
      const GroundTruth::Object truth = truth_of(*frame.truth, j);
      outcomes.back().objects[j].visible = truth.visible_fraction >= 0.2f;
      outcomes.back().objects[j].centroid_m = truth.centroid_m;
    }
    const double arrival_s = at_truth ? busy_until_s : double(i) / *rate;  // none dropped
    if (pending && busy_until_s <= arrival_s) {  // freed before this frame came: takes the last
      const double start = busy_until_s;
      busy_until_s = start + process(std::move(pending->first), pending->second);
      pending.reset();
    }
    if (busy_until_s <= arrival_s) {
      busy_until_s = arrival_s + process(frame, i);
    } else {
      pending.emplace(frame, i);  // a frame still waiting is replaced: dropped
    }
  }
  if (pending) process(std::move(pending->first), pending->second);
  progress.Clear();

  if (args.Has("frames-out")) {  // one JSON line per frame, for a look at what happened
    std::string log;
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
      const Outcome& o = outcomes[i];
      JsonWriter j;
      j.BeginObject().Key("frame").Value(i).Key("processed").Value(o.processed);
      j.Key("objects").BeginArray();
      for (const ObjectOutcome& oo : o.objects) {
        j.BeginObject().Key("visible").Value(oo.visible).Key("within").Value(oo.good);
        j.Key("centroid_m").Vector3(oo.centroid_m);
        j.Key("wrong").Value(oo.wrong).Key("error_cm").Value(oo.error_cm);
        j.Key("error_deg").Value(oo.error_deg);
        if (oo.error_cm >= 0) {  // where the instance scored was, and where the truth was
          const Eigen::Matrix4f pose = oo.pose, truth = oo.truth;
          j.Key("at_m").Vector3(pose.block<3, 1>(0, 3));
          j.Key("truth_at_m").Vector3(truth.block<3, 1>(0, 3));
        }
        j.EndObject();
      }
      j.EndArray();
      if (o.looked_at_m) j.Key("looked_at_m").Vector3(*o.looked_at_m);
      j.Key("states").Value(o.states).Key("reason").Value(o.reason).EndObject();
      log += j.str() + "\n";
    }
    std::string error;
    if (!WriteBytes(args.Get("frames-out"), log, &error)) {
      err << "saccade bench-track: " << error << "\n";
      return kExitFailure;
    }
  }
  // Visible frames count once per object; re-acquisition is each object's own.
  for (const Outcome& o : outcomes) {
    ++t.frames;
    if (o.processed) ++t.processed;
    if (std::any_of(o.objects.begin(), o.objects.end(),
                    [](const ObjectOutcome& oo) { return oo.wrong; }))
      ++t.wrong;
  }
  for (std::size_t j = 0; j < objects; ++j) {
    bool was_visible = false;
    int since_appeared = -1;  // visible frames since it (re)appeared, not yet re-acquired
    for (const Outcome& o : outcomes) {
      const ObjectOutcome& oo = o.objects[j];
      if (oo.visible) ++t.visible;
      if (oo.visible && oo.good) ++t.within;
      if (oo.visible && !was_visible) {
        ++t.reappearances;
        since_appeared = 0;
      }
      was_visible = oo.visible;
      if (since_appeared < 0 || !oo.visible) continue;
      if (oo.good) {
        t.max_reacquire = std::max(t.max_reacquire, since_appeared);
        since_appeared = -1;
      } else {
        ++since_appeared;
      }
    }
    if (since_appeared >= 0) {  // never found again before the sequence ended
      ++t.never_reacquired;
      t.max_reacquire = std::max(t.max_reacquire, since_appeared);
    }
  }
  // Gone from sight (its truth's visible share under 0.2): processed frames an object was still
  // held (an actionable instance of its model) before its track let go: LOST is raised when it
  // is 0 or 1. Held through to its return or the end counts every frame it was gone.
  for (std::size_t j = 0; j < objects; ++j) {
    bool was_visible = false;
    int held = -1;  // since it went: frames held, -1 when let go or visible
    for (const Outcome& o : outcomes) {
      const ObjectOutcome& oo = o.objects[j];
      if (!oo.visible && was_visible) ++t.disappearances, held = 0;
      was_visible = oo.visible;
      if (oo.visible || held < 0 || !o.processed) {
        if (oo.visible && held >= 0) t.max_held_after_gone = std::max(t.max_held_after_gone, held);
        if (oo.visible) held = -1;
        continue;
      }
      if (oo.error_cm >= 0) {
        ++held;
      } else {
        t.max_held_after_gone = std::max(t.max_held_after_gone, held);
        held = -1;
      }
    }
    if (held >= 0) t.max_held_after_gone = std::max(t.max_held_after_gone, held);
  }
  // The target's error in its visible frames where a pose was held.
  std::vector<double> error_cm, error_deg;
  for (const Outcome& o : outcomes)
    if (o.objects[0].visible && o.objects[0].error_cm >= 0) {
      error_cm.push_back(o.objects[0].error_cm);
      error_deg.push_back(o.objects[0].error_deg);
    }
  // Drift: its error in the first and the last tenth of those frames (a long run's ends).
  const std::size_t tenth = std::max<std::size_t>(1, error_cm.size() / 10);
  const std::vector<double> first_tenth(error_cm.begin(),
                                        error_cm.begin() + long(std::min(tenth, error_cm.size())));
  const std::vector<double> last_tenth(error_cm.end() - long(std::min(tenth, error_cm.size())),
                                       error_cm.end());
  // Its error frame to frame: between two frames in a row that both held it, how far its
  // motion (centroid shift, turn) differs from the truth's. A truth with a slowly varying
  // error of its own (a tag board's) cancels out of it; a symmetric object's turn too.
  std::vector<double> step_cm, step_deg;
  for (std::size_t i = 1; i < outcomes.size(); ++i) {
    const ObjectOutcome &a = outcomes[i - 1].objects[0], &b = outcomes[i].objects[0];
    if (a.error_cm < 0 || b.error_cm < 0) continue;
    const PoseError e = StepError(a.pose, b.pose, a.truth, b.truth, centres[0]);
    step_cm.push_back(100 * e.translation_m);
    step_deg.push_back(e.rotation_deg);
  }
  const std::string name = args.Get("name", args.Get("source"));
  const double share = t.visible > 0 ? double(t.within) / t.visible : 0;
  char line[400];
  std::snprintf(
      line, sizeof line,
      "%s: %d/%d visible frames within %.0f cm and %.0f deg (%.1f%%), re-acquired within "
      "%d frames%s, %d frames on a wrong place; %d of %d frames dropped at %.0f Hz, "
      "%d recognized; track p50 %.2f ms, frame p50 %.1f ms p99 %.1f ms (while tracking %.1f ms)",
      name.c_str(), t.within, t.visible, *tol_cm, *tol_deg, 100 * share, t.max_reacquire,
      t.never_reacquired ? " (once never)" : "", t.wrong, t.frames - t.processed, t.frames, *rate,
      t.recognized, t.track_ms.Percentile(0.5), t.frame_ms.Percentile(0.5),
      t.frame_ms.Percentile(0.99), t.tracking_frame_ms.Percentile(0.99));
  out << line << "\n";
  JsonWriter j;
  j.BeginObject()
      .Key("sequence")
      .Value(name)
      .Key("objects")
      .Value(objects)
      .Key("visible_frames")
      .Value(t.visible)
      .Key("tracked_within_tolerance")
      .Value(share)
      .Key("tracked_frames")
      .Value(t.within)
      .Key("tolerance_cm")
      .Value(*tol_cm)
      .Key("tolerance_deg")
      .Value(*tol_deg)
      .Key("reappearances")
      .Value(t.reappearances)
      .Key("max_reacquire_frames")
      .Value(t.max_reacquire)
      .Key("never_reacquired")
      .Value(t.never_reacquired)
      .Key("target_frames_with_pose")
      .Value(error_cm.size())
      .Key("error_cm_p50")
      .Value(Quantile(error_cm, 0.5))
      .Key("error_cm_p90")
      .Value(Quantile(error_cm, 0.9))
      .Key("error_deg_p50")
      .Value(Quantile(error_deg, 0.5))
      .Key("error_deg_p90")
      .Value(Quantile(error_deg, 0.9))
      .Key("step_pairs")
      .Value(step_cm.size())
      .Key("step_error_cm_p50")
      .Value(Quantile(step_cm, 0.5))
      .Key("step_error_cm_p90")
      .Value(Quantile(step_cm, 0.9))
      .Key("step_error_deg_p50")
      .Value(Quantile(step_deg, 0.5))
      .Key("step_error_deg_p90")
      .Value(Quantile(step_deg, 0.9))
      .Key("error_cm_p50_first_tenth")
      .Value(Quantile(first_tenth, 0.5))
      .Key("error_cm_p50_last_tenth")
      .Value(Quantile(last_tenth, 0.5))
      .Key("disappearances")
      .Value(t.disappearances)
      .Key("max_frames_held_after_gone")
      .Value(t.max_held_after_gone)
      .Key("wrong_object_frames")
      .Value(t.wrong)
      .Key("recognized_frames")
      .Value(t.recognized)
      .Key("track_ms_p50")
      .Value(t.track_ms.Percentile(0.5))
      .Key("track_ms_p99")
      .Value(t.track_ms.Percentile(0.99))
      .Key("recognize_ms_p50")
      .Value(t.recognize_ms.Percentile(0.5))
      .Key("recognize_ms_p99")
      .Value(t.recognize_ms.Percentile(0.99))
      .Key("frame_ms_p50")
      .Value(t.frame_ms.Percentile(0.5))
      .Key("frame_ms_p99")
      .Value(t.frame_ms.Percentile(0.99))
      .Key("tracking_frame_ms_p99")
      .Value(t.tracking_frame_ms.Percentile(0.99))
      .Key("rate_hz")
      .Value(*rate)
      .Key("frames_at_30hz")
      .Value(t.frames)
      .Key("dropped_at_30hz")
      .Value(t.frames - t.processed)
      .EndObject();
  out << j.str() << "\n";
  return kExitOk;
}

}  // namespace saccade
