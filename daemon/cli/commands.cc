#include "daemon/cli/commands.h"
#include "daemon/cli/progress.h"

#include "core/candidates.h"
#include "core/eval/reference_pipeline.h"
#include "core/fail.h"
#include "core/features.h"
#include "core/recognition.h"
#include "core/sim/scenario.h"
#include "daemon/args.h"
#include "daemon/cli/recognize_library.h"
#include "daemon/eval/overlays.h"
#include "daemon/tbb_parallel.h"
#include "io/base/json.h"
#include "io/config/config.h"
#include "io/formats/cloud_io.h"
#include "io/sources/model_source.h"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iterator>
#include <ostream>

namespace saccade {
namespace {

namespace fs = std::filesystem;

// Everything a subcommand needs before it can run: options, model and scene.
struct Inputs {
  RecognitionConfig config;
  Cloud model;                     // every view's points
  std::vector<Cloud> model_views;  // as described (one for a captured model)
  Cloud scene;
};

}  // namespace

int Usage(std::ostream& err, const std::string& command, const std::string& message) {
  err << "saccade " << command << ": " << message << "\n";
  return kExitUsage;
}

namespace {

// Loads --config, --model and --scene; prints one line and returns the exit code on failure.
// With `with_model` false, the scene alone (several models are read by their own command).
std::optional<int> LoadInputs(const Args& args, const std::string& command, Inputs* in,
                              std::ostream& err, bool with_model = true) {
  std::string error;
  if (args.Has("config") && !LoadRecognitionConfig(args.Get("config"), &in->config, &error)) {
    err << "saccade " << command << ": " << error << "\n";
    return kExitFailure;
  }
  for (const char* name : {"model", "scene"}) {
    if (!args.Has(name)) return Usage(err, command, std::string("missing --") + name);
    if (!with_model && std::string(name) == "model") continue;
    // The model is read once, as its views (one for a captured model).
    std::optional<Cloud> cloud;
    if (std::string(name) == "model") {
      if (auto views = LoadModelViews(args.Get(name), &error)) {
        cloud = views->size() == 1 ? views->front() : MergeViews(*views);
        in->model_views = std::move(*views);
      }
    } else {
      cloud = LoadCloud(args.Get(name), &error);
    }
    if (!cloud) {
      err << "saccade " << command << ": " << error << "\n";
      return kExitFailure;
    }
    if (CountFinite(*cloud) == 0) {
      err << "saccade " << command << ": " << args.Get(name) << ": cloud has no valid point\n";
      return kExitFailure;
    }
    (std::string(name) == "model" ? in->model : in->scene) = std::move(*cloud);
  }
  return std::nullopt;
}

void WriteMatrix(JsonWriter& j, const Eigen::Matrix4f& m) {
  j.BeginArray();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) j.Value(static_cast<double>(m(r, c)));
  j.EndArray();
}

// The radii a run used (fitted to the model with radii_from_model), by config key.
std::vector<std::pair<const char*, float>> RadiiUsed(const ModelDescription& model,
                                                     const RecognitionOptions& given) {
  const RecognitionOptions o = RadiiForModel(given, model.scale());
  return {{"model_keypoint_radius_m", o.model_keypoint_radius_m},
          {"scene_keypoint_radius_m", o.scene_keypoint_radius_m},
          {"shot_radius_m", o.scene_shot_radius_m},
          {"lrf_radius_m", o.scene_lrf_radius_m},
          {"hough_bin_m", o.hough_bin_m}};
}

std::string ResultJson(const RecognitionResult& r, const ModelDescription& model,
                       const RecognitionOptions& options) {
  JsonWriter j;
  j.BeginObject().Key("model").BeginObject();
  j.Key("size_m").Value(double(model.scale().size_m));
  j.Key("spacing_m").Value(double(model.scale().spacing_m)).EndObject();
  j.Key("radii").BeginObject();
  for (const auto& [key, value] : RadiiUsed(model, options)) j.Key(key).Value(double(value));
  j.EndObject();
  j.Key("instances").BeginArray();
  for (const Detection& d : r.instances) {
    j.BeginObject().Key("pose");
    WriteMatrix(j, d.model_to_scene);
    j.Key("votes").Value(d.votes).Key("centroid").Vector3(d.centroid_m);
    j.Key("fitness").Value(double(d.fitness)).Key("coverage").Value(double(d.coverage));
    j.Key("colour_agreement").Value(double(d.colour_agreement));
    j.Key("confidence").Value(double(d.confidence));
    j.EndObject();
  }
  j.EndArray().Key("timing_ms").BeginObject();
  for (const auto& [stage, ms] : r.stats.stage_ms) j.Key(stage).Value(ms);
  j.EndObject();
  j.Key("points").Value(r.stats.TotalPoints()).Key("keypoints").Value(r.stats.TotalKeypoints());
  j.Key("levels").BeginArray();
  for (std::size_t k = 0; k < r.stats.level_points.size(); ++k)
    j.BeginObject()
        .Key("points")
        .Value(r.stats.level_points[k])
        .Key("keypoints")
        .Value(r.stats.level_keypoints[k])
        .EndObject();
  j.EndArray();
  j.Key("described").Value(r.stats.described).Key("correspondences").Value(r.stats.correspondences);
  j.Key("hypotheses").Value(r.stats.hypotheses);
  j.EndObject();
  return j.str();
}

void PrintResult(const RecognitionResult& r, const ModelDescription& model,
                 const RecognitionOptions& options, std::ostream& out) {
  out << std::fixed << std::setprecision(4);
  out << "model: size " << model.scale().size_m << " m, point spacing " << model.scale().spacing_m
      << " m; radii" << (options.radii_from_model ? " (fitted to the model)" : "") << ":";
  for (const auto& [key, value] : RadiiUsed(model, options)) out << " " << key << " " << value;
  out << "\n" << r.instances.size() << " instance(s)\n";
  for (std::size_t i = 0; i < r.instances.size(); ++i) PrintInstance(i, r.instances[i], "", out);
  out << "level  points  keypoints\n";
  for (std::size_t k = 0; k < r.stats.level_points.size(); ++k)
    out << std::setw(5) << k << std::setw(8) << r.stats.level_points[k] << std::setw(11)
        << r.stats.level_keypoints[k] << "\n";
  out << "described " << r.stats.described << ", correspondences " << r.stats.correspondences
      << ", hypotheses " << r.stats.hypotheses << "\n";
  out << std::setprecision(2) << "timing ms:";
  for (const auto& [stage, ms] : r.stats.stage_ms) out << " " << stage << " " << ms;
  out << "\n";
}

// The places saccaded's search would look at for the model in an organized scene, best first,
// with what scored each (core/candidates.h, with the candidates section's defaults).
int PrintCandidates(const ModelDescription& model, const Cloud& scene, const std::string& where,
                    std::ostream& out, std::ostream& err) {
  const std::optional<CameraIntrinsics> camera = EstimateIntrinsics(scene);
  if (!camera) {
    err << "saccade recognize: " << where
        << ": --candidates needs an organized scene (one point per pixel)\n";
    return kExitFailure;
  }
  const ModelSignature signature = SignModel(model);
  CandidateStats stats;
  const std::vector<Candidate> candidates =
      ProposeCandidates(scene, *camera, signature, CandidateOptions{}, &stats);
  out << std::fixed << std::setprecision(3) << "model: radius " << signature.radius_m
      << " m, seen area " << signature.seen_area_m2 << " m2 (" << signature.seen_area_min_m2 << "-"
      << signature.seen_area_max_m2 << "), thickness " << signature.thickness_m << " m"
      << (signature.coloured ? ", coloured" : "") << "\n"
      << candidates.size() << " candidate(s) of " << stats.coarse_points << " coarse points ("
      << stats.above_plane << " off the " << (stats.plane_found ? "table plane" : "frame, no plane")
      << ")\nrank  centre (m)               score  fill   shape  colour apart  points\n";
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Candidate& c = candidates[i];
    out << std::setw(4) << i << "  " << std::setw(6) << c.centre_m.x() << ' ' << std::setw(6)
        << c.centre_m.y() << ' ' << std::setw(6) << c.centre_m.z() << "    " << c.score << "  "
        << c.fill << "  " << c.shape << "  " << c.colour << "  " << c.apart << "  " << c.points
        << "\n";
  }
  return kExitOk;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

std::optional<int> CheckPngPath(const std::string& path, const std::string& command,
                                std::ostream& err) {
  const fs::path render = path;
  std::error_code ec;
  const fs::path folder = render.has_parent_path() ? render.parent_path() : fs::path(".");
  if (render.extension() != ".png")
    return Usage(err, command, "--render expects a .png path, got '" + render.string() + "'");
  if (!fs::is_directory(folder, ec) || fs::is_directory(render, ec)) {
    err << "saccade " << command << ": " << render.string() << ": cannot write there ("
        << (fs::is_directory(render, ec) ? "a folder" : "no folder " + folder.string()) << ")\n";
    return kExitFailure;
  }
  return std::nullopt;
}

int RunRecognize(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade recognize",
            "Finds the model in one scene and prints each instance's pose (camera frame, "
            "metres), its centroid and its votes.");
  args.Value("model", "M.pcd[,N.pcd...]",
             "the object's model: a PCD cloud in metres (required); several, comma-separated, "
             "are searched at once as a library and each instance names its model")
      .Value("scene", "S.pcd", "the scene: an organized or unorganized PCD cloud (required)")
      .Value("fovea", "x,y,z",
             "the fixation point, in metres in the camera frame (required "
             "unless --plain)")
      .Switch("plain", "recognize on the whole scene, without foveation (the gold standard)")
      .Value("config", "FILE.yaml",
             "recognition settings over Saccade's defaults "
             "(configs/saccaded.yaml lists them)")
      .Value("threads", "N", "worker threads (default: one per core)")
      .Switch("json", "print one JSON object instead of text")
      .Value("render", "OUT.png",
             "also draw the scene with each instance's model points, box and confidence")
      .Switch("candidates",
              "print instead where saccaded's search would look for the model in this "
              "organized scene, best first, and what scored each place");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  if (args.Has("render"))
    if (auto code = CheckPngPath(args.Get("render"), "recognize", err)) return *code;
  SceneQuery query;
  query.foveated = !args.Has("plain") && !args.Has("candidates");
  if (args.Has("fovea")) {
    auto f = Args::ParseVector3(args.Get("fovea"));
    if (!f)
      return Usage(err, "recognize",
                   "--fovea expects x,y,z in metres, got '" + args.Get("fovea") + "'");
    query.fovea_m = *f;
  } else if (query.foveated) {
    return Usage(err, "recognize", "missing --fovea x,y,z (or --plain)");
  }
  int threads = 0;
  if (args.Has("threads")) {
    auto t = Args::ParsePositiveInt(args.Get("threads"));
    if (!t) return Usage(err, "recognize", "--threads expects a positive integer");
    threads = *t;
  }
  const std::vector<std::string> specs = Args::ParseList(args.Get("model"));
  Inputs in;
  if (specs.size() > 1) {
    if (args.Has("render"))
      return Usage(err, "recognize", "--render draws one model: give one --model");
    if (args.Has("candidates"))
      return Usage(err, "recognize", "--candidates ranks one model's places: give one --model");
    if (auto code = LoadInputs(args, "recognize", &in, err, false)) return *code;
    query.fovea = in.config.fovea;
    return RecognizeLibraryCommand(specs, in.scene, query, in.config.recognition,
                                   MakeTbbParallelFor(threads), args.Has("json"), out, err);
  }
  if (auto code = LoadInputs(args, "recognize", &in, err)) return *code;
  query.fovea = in.config.fovea;
  auto model = DescribeModel(in.model_views, in.config.recognition, &error);
  if (!model) {
    err << "saccade recognize: " << args.Get("model") << ": " << error << "\n";
    return kExitFailure;
  }
  if (args.Has("candidates")) return PrintCandidates(*model, in.scene, args.Get("scene"), out, err);
  const RecognitionResult result = Recognize(*model, in.scene, query, in.config.recognition,
                                             MakeTbbParallelFor(threads), &error);
  if (!error.empty()) {
    err << "saccade recognize: " << args.Get("scene") << ": " << error << "\n";
    return kExitFailure;
  }
  if (args.Has("render")) {
    // The intrinsics an organized scene's points imply, else those the project assumes.
    const CameraIntrinsics camera = EstimateIntrinsics(in.scene).value_or(CameraIntrinsics{});
    std::vector<OverlayMark> marks;
    for (std::size_t i = 0; i < result.instances.size(); ++i)
      marks.push_back({result.instances[i].model_to_scene,
                       kInstanceColours[i % std::size(kInstanceColours)],
                       InstanceLabel(i, result.instances[i])});
    if (!WriteOverlayPng(args.Get("render"), RenderOverlay(in.scene, camera, in.model, marks),
                         &error)) {
      err << "saccade recognize: " << OneLine(error) << "\n";
      return kExitFailure;
    }
  }
  if (args.Has("json"))
    out << ResultJson(result, *model, in.config.recognition) << "\n";
  else
    PrintResult(result, *model, in.config.recognition, out);
  return kExitOk;
}

namespace {

// One configuration's outcome over the bench frames.
struct BenchRun {
  std::string name;
  std::vector<RecognitionResult> runs;
  std::optional<PoseError> error;  // of the best instance, when --truth is given
  bool found = false;
};

void Judge(BenchRun* run, const std::optional<Eigen::Matrix4f>& truth,
           const Eigen::Vector3f& model_centroid) {
  const RecognitionResult& last = run->runs.back();
  if (last.instances.empty()) return;
  if (!truth) {
    run->found = true;
    return;
  }
  // The instance closest to the truth is the one that found the model; others are false.
  for (const Detection& d : last.instances) {
    const PoseError e = ComparePoses(d.model_to_scene, *truth, model_centroid);
    if (!run->error || e.translation_m < run->error->translation_m) run->error = e;
  }
  run->found = run->error->translation_m < 0.01 && run->error->rotation_deg < 3.0;
}

std::vector<std::pair<std::string, double>> StageMedians(const BenchRun& run) {
  std::vector<std::pair<std::string, double>> out;
  for (std::size_t s = 0; s < run.runs.front().stats.stage_ms.size(); ++s) {
    std::vector<double> v;
    for (const auto& r : run.runs) v.push_back(r.stats.stage_ms[s].second);
    out.emplace_back(run.runs.front().stats.stage_ms[s].first, Median(v));
  }
  return out;
}

double TotalMedian(const BenchRun& run) {
  for (const auto& [stage, ms] : StageMedians(run))
    if (stage == "total") return ms;
  return 0;
}

}  // namespace

int RunBench(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade bench",
            "Times plain recognition (the gold standard) against foveated recognition on one "
            "frame, stage by stage; medians over --frames runs.");
  args.Value("model", "M.pcd", "the object's model: a PCD cloud in metres (required)")
      .Value("scene", "S.pcd", "the scene: a PCD cloud (required)")
      .Value("fovea", "x,y,z", "the fixation point, in metres in the camera frame (required)")
      .Value("truth", "POSE.txt", "the model's true pose (a 4x4 matrix): score both runs")
      .Value("frames", "N", "runs of each pipeline (default: 10)")
      .Value("config", "FILE.yaml", "recognition settings over Saccade's defaults")
      .Value("threads", "N", "worker threads (default: one per core)")
      .Switch("json", "print one JSON object instead of text");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  if (!args.Has("fovea")) return Usage(err, "bench", "missing --fovea x,y,z");
  auto fovea = Args::ParseVector3(args.Get("fovea"));
  if (!fovea)
    return Usage(err, "bench", "--fovea expects x,y,z in metres, got '" + args.Get("fovea") + "'");
  int frames = 10, threads = 0;
  if (args.Has("frames")) {
    auto f = Args::ParsePositiveInt(args.Get("frames"));
    if (!f) return Usage(err, "bench", "--frames expects a positive integer");
    frames = *f;
  }
  if (args.Has("threads")) {
    auto t = Args::ParsePositiveInt(args.Get("threads"));
    if (!t) return Usage(err, "bench", "--threads expects a positive integer");
    threads = *t;
  }
  Inputs in;
  if (auto code = LoadInputs(args, "bench", &in, err)) return *code;
  std::optional<Eigen::Matrix4f> truth;
  if (args.Has("truth")) {
    truth = LoadPose(args.Get("truth"), &error);
    if (!truth) {
      err << "saccade bench: " << error << "\n";
      return kExitFailure;
    }
  }
  const ParallelFor parallel_for = MakeTbbParallelFor(threads);

  // The plain gold standard (paper configuration 10): PCL's stock stages, r_ks = 0.02.
  RecognitionOptions gold = in.config.recognition;
  gold.scene_keypoint_radius_m = 0.02f;
  auto reference_model = DescribeReferenceModel(in.model, gold, &error);
  auto model = DescribeModel(in.model_views, in.config.recognition, &error);
  if (!reference_model || !model) {
    err << "saccade bench: " << args.Get("model") << ": " << error << "\n";
    return kExitFailure;
  }
  SceneQuery foveated;
  foveated.fovea = in.config.fovea;
  foveated.fovea_m = *fovea;
  SceneQuery plain_fast = foveated;
  plain_fast.foveated = false;

  BenchRun plain{"plain", {}, {}, false}, plain_same{"plain_saccade_stages", {}, {}, false},
      fov{"foveated", {}, {}, false};
  // One warm-up each (caches, page faults, TBB threads), then the measured frames; on a
  // terminal, a line of progress on stderr.
  ProgressLine progress(err, ProgressLine::StderrIsATerminal());
  const auto total = static_cast<std::size_t>(3 * (frames + 1));
  std::size_t done = 0;
  for (int i = 0; i <= frames; ++i) {
    auto r = RecognizeReference(*reference_model, in.scene, gold, &error);
    if (i > 0) plain.runs.push_back(std::move(r));
    progress.Show("saccade bench: frames", ++done, total);
  }
  // The same options as the foveated run (radii fitted when they are), but r_ks = 0.02.
  RecognitionOptions gold_fast = RadiiForModel(in.config.recognition, model->scale());
  gold_fast.radii_from_model = false;
  gold_fast.scene_keypoint_radius_m = 0.02f;
  for (int i = 0; i <= frames; ++i) {
    auto r = Recognize(*model, in.scene, plain_fast, gold_fast, parallel_for, &error);
    if (i > 0) plain_same.runs.push_back(std::move(r));
    progress.Show("saccade bench: frames", ++done, total);
  }
  for (int i = 0; i <= frames; ++i) {
    auto r = Recognize(*model, in.scene, foveated, in.config.recognition, parallel_for, &error);
    if (i > 0) fov.runs.push_back(std::move(r));
    progress.Show("saccade bench: frames", ++done, total);
  }
  progress.Clear();
  const Eigen::Vector3f centroid = model->centroid();
  for (BenchRun* run : {&plain, &plain_same, &fov}) Judge(run, truth, centroid);
  const double speedup = TotalMedian(plain) / std::max(1e-9, TotalMedian(fov));
  const double speedup_same = TotalMedian(plain_same) / std::max(1e-9, TotalMedian(fov));

  if (args.Has("json")) {
    JsonWriter j;
    j.BeginObject();
    for (const BenchRun* run : {&plain, &plain_same, &fov}) {
      j.Key(run->name).BeginObject().Key("median_ms").Value(TotalMedian(*run));
      j.Key("found").Value(run->found);
      j.Key("instances").Value(run->runs.back().instances.size());
      j.Key("translation_error_m");
      run->error ? j.Value(run->error->translation_m) : j.Null();
      j.Key("rotation_error_deg");
      run->error ? j.Value(run->error->rotation_deg) : j.Null();
      j.Key("points").Value(run->runs.back().stats.TotalPoints());
      j.Key("keypoints").Value(run->runs.back().stats.TotalKeypoints());
      j.Key("stages_ms").BeginObject();
      for (const auto& [stage, ms] : StageMedians(*run)) j.Key(stage).Value(ms);
      j.EndObject().EndObject();
    }
    j.Key("speedup").Value(speedup).Key("speedup_same_stages").Value(speedup_same);
    j.Key("frames").Value(frames).EndObject();
    out << j.str() << "\n";
    return kExitOk;
  }
  out << std::fixed << std::setprecision(2);
  out << "median over " << frames << " frame(s) after one warm-up, milliseconds per stage\n";
  for (const BenchRun* run : {&plain, &plain_same, &fov}) {
    out << std::left << std::setw(22) << run->name << std::right;
    for (const auto& [stage, ms] : StageMedians(*run)) out << " " << stage << " " << ms;
    out << "\n"
        << std::setw(22) << ""
        << " points " << run->runs.back().stats.TotalPoints() << ", keypoints "
        << run->runs.back().stats.TotalKeypoints() << ", instances "
        << run->runs.back().instances.size() << ", found " << (run->found ? "yes" : "no");
    if (run->error)
      out << std::setprecision(4) << ", error " << run->error->translation_m * 100 << " cm "
          << run->error->rotation_deg << " deg" << std::setprecision(2);
    out << "\n";
  }
  out << "speed-up foveated vs plain gold standard: " << speedup << "x (vs plain with Saccade's "
      << "stages: " << speedup_same << "x)\n";
  return kExitOk;
}

int RunDemo(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade demo",
            "Renders a synthetic Kinect scene and finds in it a target modelled from another "
            "capture. Exit 1 when the target is not found.");
  args.Value("seed", "N", "the scene's random seed, a whole number >= 1 (default: 1)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  const auto seed = Args::ParsePositiveInt(args.Get("seed", "1"));
  if (!seed) return Usage(err, "demo", "--seed must be a whole number >= 1");
  const CameraIntrinsics kinect;
  const CrossCaptureCase demo = MakeDemoCase(static_cast<std::uint32_t>(*seed), kinect);
  const RecognitionOptions options;  // Saccade's defaults: radii fitted to the model
  auto model = DescribeModel(demo.model, options, &error);
  if (!model) {
    err << "saccade demo: synthetic model: " << error << "\n";
    return kExitFailure;
  }
  const Cloud& scene = demo.scene.cloud;
  const Eigen::Isometry3f& X_CO = demo.truth;
  const Eigen::Matrix4f truth = X_CO.matrix();
  const Eigen::Vector3f true_centroid = X_CO * model->centroid();
  SceneQuery query;
  query.intrinsics = kinect;
  query.fovea_m = true_centroid + Eigen::Vector3f(0.05f, -0.03f, 0.04f);  // a rough first guess
  const ParallelFor parallel_for = MakeTbbParallelFor(0);
  const RecognitionResult fov = Recognize(*model, scene, query, options, parallel_for);
  SceneQuery plain_query = query;
  plain_query.foveated = false;
  const RecognitionResult plain = Recognize(*model, scene, plain_query, options, parallel_for);
  out << "synthetic Kinect scene (seed " << *seed << "): " << CountFinite(scene)
      << " points, target among " << demo.clutter_objects << " clutter objects; model "
      << demo.model.size() << " points cut from another capture\n";
  out << std::fixed << std::setprecision(2);
  for (const auto* run : {&plain, &fov}) {
    const bool foveated = run == &fov;
    out << (foveated ? "foveated" : "plain   ") << ": " << run->instances.size() << " instance(s), "
        << run->stats.TotalPoints() << " points, " << run->stats.TotalKeypoints() << " keypoints, "
        << run->stats.stage_ms.back().second << " ms";
    if (!run->instances.empty()) {
      const PoseError e = ComparePoses(run->instances[0].model_to_scene, truth, model->centroid());
      out << ", best: " << run->instances[0].votes << " votes, error " << e.translation_m * 100
          << " cm " << e.rotation_deg << " deg";
    }
    out << "\n";
  }
  const bool found =
      !fov.instances.empty() &&
      ComparePoses(fov.instances[0].model_to_scene, truth, model->centroid()).translation_m < 0.02;
  out << (found ? "target found: within 2 cm of the truth" : "target NOT found") << "\n";
  return found ? kExitOk : kExitFailure;
}

}  // namespace saccade
