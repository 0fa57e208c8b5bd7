// `saccade eval`: recognition configurations over a dataset with ground truth, scored with the
// paper's rule (§5.3), written as CSV and Markdown tables and plotted with gnuplot.
#include "attention/attention.h"
#include "core/eval/evaluation.h"
#include "core/eval/opencv_ppf.h"
#include "core/eval/reference_pipeline.h"
#include "core/fail.h"
#include "core/features.h"
#include "core/recognition.h"
#include "core/segmentation.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/cli/progress.h"
#include "daemon/eval/evaluation.h"
#include "daemon/eval/library_bench.h"
#include "daemon/eval/overlays.h"
#include "daemon/eval/plots.h"
#include "daemon/eval/report.h"
#include "daemon/tbb_parallel.h"
#include "io/config/config.h"
#include "io/formats/cloud_io.h"
#include "io/formats/output_file.h"
#include "io/sources/frame_source.h"
#include "io/sources/model_source.h"

#include <pcl/console/print.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <ostream>
#include <random>
#include <sstream>

namespace saccade {
using namespace eval;  // the harness this command drives: its values and runner

namespace {

namespace fs = std::filesystem;
// --model and --dataset (a folder, a source spec or one PCD file), every frame with its truth:
// the generator's or recording's, or --truth-pose's; with a sphere radius, also the RANSAC
// sphere fit's. nullopt when loaded, else the exit code (the message is written to `err`).
std::optional<int> LoadDatasetScenes(const Args& args, std::optional<float> sphere_radius,
                                     int max_frames, std::vector<EvalModel>* models,
                                     std::vector<Scene>* scenes, std::ostream& err) {
  std::string error;
  const auto fail = [&](const std::string& message) {
    err << "saccade eval: " << message << "\n";
    return kExitFailure;
  };
  std::optional<Cloud> model = LoadModelCloud(args.Get("model"), &error);
  if (!model) return fail(error);
  std::optional<Eigen::Vector3f> model_centre = FiniteCentroid(*model);
  if (!model_centre) return fail(args.Get("model") + ": the model has no valid point");
  if (args.Has("model-centre")) {
    model_centre = Args::ParseVector3(args.Get("model-centre"));
    if (!model_centre)
      return Usage(err, "eval", "--model-centre expects x,y,z in the model's frame");
  }
  EvalModel& m = models->emplace_back();
  m.cloud = std::move(*model);
  m.centre = *model_centre;
  // With --truth-pose, one pose (model to scene) is the truth of every frame: a single
  // capture such as PCL's milk scene, whose pose file comes with it.
  std::optional<Eigen::Vector3f> posed_truth;
  if (args.Has("truth-pose")) {
    const auto pose = LoadPose(args.Get("truth-pose"), &error);
    if (!pose) return fail(error);
    posed_truth = (*pose * model_centre->homogeneous()).head<3>();
  }

  const std::string dataset = args.Get("dataset");
  std::error_code ec;
  SphereFitOptions sphere_options;
  if (sphere_radius) {
    sphere_options.min_radius_m = *sphere_radius * 0.75f;
    sphere_options.max_radius_m = *sphere_radius * 1.25f;
  }
  const auto add_scene = [&](Scene s) {
    s.name = "frame " + std::to_string(s.frame.sequence);
    if (posed_truth) {
      s.truth_m = *posed_truth;
    } else if (s.frame.truth) {
      s.truth_m = s.frame.truth->centroid_m;
    } else {
      error = dataset + ": frame " + std::to_string(s.frame.sequence) +
              " has no ground truth (truth.csv beside the frames, or --truth-pose)";
      return false;
    }
    if (sphere_radius) {
      if (const auto sphere = FitSphere(*s.frame.cloud, sphere_options))
        s.sphere_truth_m = sphere->centre_m;
    }
    scenes->push_back(std::move(s));
    return true;
  };
  if (fs::is_regular_file(dataset, ec)) {
    std::optional<Cloud> cloud = LoadCloud(dataset, &error);
    if (!cloud) return fail(error);
    Scene s;
    if (const auto k = EstimateIntrinsics(*cloud)) s.frame.intrinsics = *k;
    s.frame.cloud = std::make_shared<const Cloud>(std::move(*cloud));
    if (!add_scene(std::move(s))) return fail(error);
  } else {
    if (dataset.find(':') == std::string::npos && !fs::is_directory(dataset, ec))
      return fail(dataset + ": not a folder, a PCD file or a source spec");
    auto source = OpenSource(DatasetSpec(dataset), &error);
    if (!source) return fail(error);
    while (static_cast<int>(scenes->size()) < max_frames) {
      Scene s;
      const auto status = source->Next(&s.frame, &error);
      if (status == FrameSource::Status::kEnd) break;
      if (status == FrameSource::Status::kError || !add_scene(std::move(s))) return fail(error);
    }
  }
  if (scenes->empty()) return fail(dataset + ": no frames");
  return std::nullopt;
}

// Every model and scene without colour (scenes that share a capture share its stripped copy):
// what a depth-only camera gives, for recognition, verification and the candidates alike.
void StripColour(std::vector<EvalModel>* models, std::vector<Scene>* scenes) {
  const auto strip = [](Cloud* cloud) {
    for (PointT& p : *cloud) p.rgba = 0;
  };
  for (EvalModel& m : *models) strip(&m.cloud);
  std::map<const Cloud*, std::shared_ptr<const Cloud>> stripped;
  for (Scene& s : *scenes) {
    auto& copy = stripped[s.frame.cloud.get()];
    if (!copy) {
      auto c = std::make_shared<Cloud>(*s.frame.cloud);
      strip(c.get());
      copy = std::move(c);
    }
    s.frame.cloud = copy;
  }
}

// library.csv (a row per capture and size), library_instances.csv (every model's instances
// before the library chose between models) and library.md (the summary), into `dir`.
int WriteLibraryReport(const fs::path& dir, const std::vector<eval::LibraryRow>& rows,
                       std::ostream& out, std::ostream& err) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  std::string error;
  std::ostringstream csv;
  csv << "scene,models,instances,found,false_instances,descriptions,ms,describe_ms,match_ms,"
         "group_ms,verify_ms,costliest_alone_ms,detail\n";
  for (const eval::LibraryRow& r : rows)
    csv << r.scene << "," << r.size << "," << r.instances << "," << r.found << ","
        << r.false_instances << "," << r.descriptions << "," << r.ms << "," << r.describe_ms << ","
        << r.match_ms << "," << r.group_ms << "," << r.verify_ms << "," << r.costliest_alone_ms
        << "," << r.detail << "\n";
  std::ostringstream instances;
  instances << "scene,models,identity,label,kept,confidence,fitness,coverage,continued,colour,"
               "texture,votes,matches,model_points,model_size_m,spacing_m,x,y,z\n";
  for (const eval::LibraryRow& r : rows)
    for (const eval::LibraryInstance& c : r.candidates)
      instances << r.scene << "," << r.size << "," << c.identity << "," << c.label << ","
                << int(c.kept) << "," << c.confidence << "," << c.fitness << "," << c.coverage
                << "," << c.continued << "," << c.colour_agreement << "," << c.texture_agreement
                << "," << c.votes << "," << c.matches << "," << c.model_points << ","
                << c.model_size_m << "," << c.spacing_m << "," << c.centroid_m.x() << ","
                << c.centroid_m.y() << "," << c.centroid_m.z() << "\n";
  const std::string summary = eval::LibrarySummary(rows);
  if (ec || !WriteBytes((dir / "library.csv").string(), csv.str(), &error) ||
      !WriteBytes((dir / "library_instances.csv").string(), instances.str(), &error) ||
      !WriteBytes((dir / "library.md").string(), summary, &error)) {
    err << "saccade eval: " << (ec ? dir.string() + ": " + ec.message() : error) << "\n";
    return kExitFailure;
  }
  out << summary << "written to " << dir.string()
      << "/: library.csv library_instances.csv library.md\n";
  return kExitOk;
}

}  // namespace

int RunEval(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade eval",
            "Runs recognition configurations over frames with ground truth (--dataset and "
            "--model) or over labelled cross-capture cases (--cases); writes Table 7 style "
            "tables (CSV, Markdown), every trial's counts and stage times, TP/FP against the "
            "distance threshold, the fovea-distance sweep, and their PNG plots (gnuplot); an "
            "image of every missed or false case in overlays/.");
  args.Value("configs", "FILE.yaml",
             "the configurations to compare (required; "
             "configs/paper-configs.yaml)")
      .Value("dataset", "DIR|SPEC|FILE.pcd", "the frames: a folder, a source spec or one PCD")
      .Value("model", "M.pcd", "the object's model, with --dataset")
      .Value("model-centre", "x,y,z", "the model's centre in metres (default: its centroid)")
      .Value("truth-pose", "POSE.txt", "the model's true pose in every frame (a 4x4 matrix)")
      .Value("sphere-radius", "R", "also score with a sphere of R metres fitted to the truth")
      .Value("frames", "N", "use at most N frames of the dataset")
      .Value("cases", "CASES.yaml",
             "labelled cross-capture cases (they bring models and "
             "scenes)")
      .Value("data", "DIR", "where the cases' files are (default: ../shared/data)")
      .Value("protocols", "a,b,c",
             "with --cases: the cross-capture protocols to run "
             "(default: a)")
      .Value("model-source", "case|other-captures",
             "with --cases: each case's model is its model capture (case, the default), or every "
             "other capture of its object in the file, never the scene's, aligned into one "
             "model of several views (other-captures)")
      .Value("library", "N,...|all",
             "with --cases: instead of the protocols, search each capture the cases search for "
             "every identity at once (libraries of N models, `all` for every identity; each "
             "model made of the identity's other captures) with the first configuration's "
             "recognition on the whole frame, scored against identities.csv; writes "
             "library.csv and library.md")
      .Switch("separately",
              "with --library: the baseline, each model recognized on its own as before the "
              "library (radii as fitted, one description of the frame and one index each)")
      .Value("only", "NAME,...", "with --cases: run only these objects")
      .Value("every", "N", "with --cases: run every Nth case (default: 1)")
      .Value("out", "DIR", "where the tables and plots go (default: eval-out)")
      .Value("sweep", "NAME,...", "configurations to sweep the fovea's distance with")
      .Value("reference", "NAME", "the configuration speed-ups are against (default: 10)")
      .Value("repeat", "N", "time each trial N times and keep the median (default: 1)")
      .Switch("no-colour",
              "strip the colour from every model and scene (a depth-only camera's view)")
      .Switch("texture",
              "with --cases: also measure each instance's texture support (instances.csv)")
      .Switch("no-plots", "write no PNG plots")
      .Switch("no-overlays", "write no image of the missed and false cases (overlays/)")
      .Value("replot", "DIR",
             "only redraw the plots of an earlier run from its CSV files in DIR (runs nothing)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  if (args.Has("replot")) {
    std::vector<std::string> pngs;
    if (!WritePlots(args.Get("replot"), &pngs, &error)) {
      err << "saccade eval: " << error << "\n";
      return kExitFailure;
    }
    out << "written to " << args.Get("replot") << "/: plot.gp";
    for (const std::string& png : pngs) out << " " << png;
    out << "\n";
    return kExitOk;
  }
  const bool cases = args.Has("cases");
  if (cases && (args.Has("dataset") || args.Has("model")))
    return Usage(err, "eval", "--cases brings its own models and scenes: no --dataset or --model");
  for (const char* required : {"configs", "dataset", "model"}) {
    if (cases && std::string(required) != "configs") break;  // --cases brings the rest
    if (!args.Has(required)) return Usage(err, "eval", std::string("missing --") + required);
  }
  const auto fail = [&](const std::string& message) {
    err << "saccade eval: " << message << "\n";
    return kExitFailure;
  };
  // PCL's stock stages (the gold standard) warn for every keypoint with a NaN normal nearby;
  // on thousands of keypoints that buries the results.
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);

  std::vector<EvalConfiguration> configs;
  // Each entry may set how protocol (c)'s attention loop searches (saccaded's sections).
  std::map<std::size_t, SearchOptions> search_of;  // nodes stay put while the file is read
  const ExtraSections extra = {
      {"attention", [&](std::size_t i) { return KeysOf(&search_of[i].attention); }},
      {"candidates", [&](std::size_t i) { return KeysOf(&search_of[i].candidates); }}};
  if (!LoadEvalConfigurations(args.Get("configs"), RecognitionConfig{}, &configs, &error, extra))
    return fail(error);
  std::vector<SearchOptions> search(configs.size());
  for (std::size_t c = 0; c < configs.size(); ++c) {
    if (const auto it = search_of.find(c); it != search_of.end()) search[c] = it->second;
    std::string why;
    if (!search[c].attention.IsValid(&why) || !search[c].candidates.IsValid(&why))
      return fail(args.Get("configs") + ": configurations[" + std::to_string(c) + "] (" +
                  configs[c].name + "): " + why);
  }
  std::optional<float> sphere_radius;
  if (args.Has("sphere-radius")) {
    const auto r = Args::ParseNumber(args.Get("sphere-radius"));
    if (!r || !(*r > 0)) return Usage(err, "eval", "--sphere-radius expects metres > 0");
    sphere_radius = static_cast<float>(*r);
  }
  int max_frames = 1 << 30;
  if (args.Has("frames")) {
    const auto n = Args::ParsePositiveInt(args.Get("frames"));
    if (!n) return Usage(err, "eval", "--frames expects a positive integer");
    max_frames = *n;
  }
  const auto repeat = Args::ParsePositiveInt(args.Get("repeat", "1"));
  if (!repeat) return Usage(err, "eval", "--repeat expects a positive integer");
  const std::vector<std::string> sweep_names = Args::ParseList(args.Get("sweep"));
  for (const std::string& name : sweep_names)
    if (std::none_of(configs.begin(), configs.end(),
                     [&](const EvalConfiguration& c) { return c.name == name; }))
      return fail("--sweep: no configuration named '" + name + "'");

  if (!cases &&
      (args.Has("protocols") || args.Has("only") || args.Has("every") || args.Has("model-source")))
    return Usage(err, "eval",
                 "--protocols, --only, --every and --model-source apply to --cases only");
  const std::string model_source = args.Get("model-source", "case");
  if (model_source != "case" && model_source != "other-captures")
    return Usage(err, "eval", "--model-source expects case or other-captures");
  std::vector<eval::Protocol> protocols;  // --cases only
  for (const std::string& p : Args::ParseList(args.Get("protocols", cases ? "a" : ""))) {
    if (p.size() != 1 || p[0] < 'a' || p[0] > 'c')
      return Usage(err, "eval", "--protocols expects a list of a, b, c (e.g. a,b,c)");
    protocols.push_back(eval::Protocol(p[0] - 'a'));
  }

  if (args.Has("library")) {
    if (!cases) return Usage(err, "eval", "--library applies to --cases only");
    eval::LibraryBenchOptions library;
    for (const std::string& size : Args::ParseList(args.Get("library"))) {
      const auto n = size == "all" ? std::optional<int>(0) : Args::ParsePositiveInt(size);
      if (!n) return Usage(err, "eval", "--library expects sizes such as 1,5,10,all");
      library.sizes.push_back(*n);
    }
    const auto every = Args::ParsePositiveInt(args.Get("every", "1"));
    if (!every) return Usage(err, "eval", "--every expects a positive integer");
    library.every = *every;
    library.separately = args.Has("separately");
    library.recognition = configs.front().config.recognition;
    // One pass over the whole frame: every keypoint, not a window of the daemon's budget.
    library.recognition.max_scene_keypoints = 0;
    library.parallel = MakeTbbParallelFor();
    library.log = &out;
    std::vector<eval::LibraryRow> rows;
    if (!eval::RunLibraryBench(args.Get("cases"), args.Get("data", "../shared/data"), library,
                               &rows, &error))
      return fail(error);
    return WriteLibraryReport(args.Get("out", "eval-out"), rows, out, err);
  }
  std::vector<EvalModel> models;
  std::vector<Scene> scenes;
  if (cases) {
    const std::vector<std::string> only = Args::ParseList(args.Get("only"));
    const auto every = Args::ParsePositiveInt(args.Get("every", "1"));
    if (!every) return Usage(err, "eval", "--every expects a positive integer");
    eval::CaseModels case_models;
    case_models.other_captures = model_source == "other-captures";
    case_models.parallel = MakeTbbParallelFor();
    case_models.log = &out;
    if (!LoadCaseScenes(args.Get("cases"), args.Get("data", "../shared/data"), only, *every,
                        &models, &scenes, &error, case_models))
      return fail(error);
  } else if (auto code =
                 LoadDatasetScenes(args, sphere_radius, max_frames, &models, &scenes, err)) {
    return *code;
  }
  if (args.Has("no-colour")) StripColour(&models, &scenes);

  const fs::path dir = args.Get("out", "eval-out");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return fail(dir.string() + ": cannot create it (" + ec.message() + ")");
  Runner runner(models, MakeTbbParallelFor(), *repeat);
  runner.MeasureTexture(args.Has("texture"));
  // On a terminal, a line redrawn with the scenes done and the time left.
  ProgressLine progress(err, ProgressLine::StderrIsATerminal());
  std::string step;  // what the runner runs now
  runner.Report([&](std::size_t done, std::size_t total) { progress.Show(step, done, total); });
  // Per configuration: the trials with the fovea on the truth, and for swept ones the Fig. 10
  // offsets too (the first of which is the truth itself).
  const std::vector<Eigen::Vector3f> sweep_offsets = SweepOffsets();
  std::vector<std::vector<Trial>> trials(configs.size());
  std::vector<std::vector<std::vector<Trial>>> swept(configs.size());
  std::vector<std::vector<std::vector<Acquisition>>> acquired(configs.size());
  std::vector<double> mean_ms(configs.size());
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const bool sweep =
        std::find(sweep_names.begin(), sweep_names.end(), configs[c].name) != sweep_names.end();
    std::vector<std::vector<Trial>> per_offset;
    step = "saccade eval: configuration " + configs[c].name;
    if (!runner.Run(
            configs[c], scenes, sweep ? sweep_offsets.size() : 1,
            [&](std::size_t k, std::size_t i) { return scenes[i].truth_m + sweep_offsets[k]; },
            &per_offset, sweep ? &acquired[c] : nullptr, &error, search[c]))
      return fail("configuration " + configs[c].name + ": " + error);
    trials[c] = per_offset.front();
    mean_ms[c] = MeanMs(trials[c]);
    if (sweep) swept[c] = std::move(per_offset);
    progress.Clear();
    err << "saccade eval: configuration " << configs[c].name << " done\n";
  }
  if (cases) {
    // The benchmark's protocols; (a) is the trials above.
    std::vector<std::vector<eval::ProtocolRun>> runs(configs.size());
    for (std::size_t c = 0; c < configs.size(); ++c)
      for (eval::Protocol p : protocols) {
        // Where the fovea is matters to foveated recognition only.
        if (p != eval::Protocol::kOnObject &&
            configs[c].pipeline != EvalConfiguration::Pipeline::kFoveated)
          continue;
        eval::ProtocolRun run;
        run.protocol = p;
        std::vector<std::vector<Trial>> per;
        std::vector<std::vector<Acquisition>> acquisitions;
        const bool acquire = p == eval::Protocol::kAcquisition;
        step = "saccade eval: configuration " + configs[c].name + ", protocol " +
               eval::ProtocolName(p);
        if (p == eval::Protocol::kOnObject) {
          run.trials = trials[c];
        } else if (!runner.Run(
                       configs[c], scenes, 1,
                       [&](std::size_t, std::size_t i) {
                         return acquire ? Eigen::Vector3f(0, 0, 1)
                                        : scenes[i].truth_m + OffObject(i);
                       },
                       &per, acquire ? &acquisitions : nullptr, &error, search[c])) {
          return fail("configuration " + configs[c].name + ": " + error);
        } else {
          run.trials = std::move(per.front());
          if (acquire) run.acquisitions = std::move(acquisitions.front());
        }
        runs[c].push_back(std::move(run));
        progress.Clear();
        err << "saccade eval: configuration " << configs[c].name << ", protocol "
            << eval::ProtocolName(p) << " done\n";
      }
    if (!eval::WriteCaseReport(args.Get("cases"), configs, models, scenes, runs, dir, out, &error))
      return fail(error);
  }
  const std::string reference = args.Get("reference", "10");
  double reference_ms = 0;
  for (std::size_t c = 0; c < configs.size(); ++c)
    if (configs[c].name == reference) reference_ms = mean_ms[c];

  // Table 7.
  TextFile csv(dir / "table.csv"), md(dir / "table.md");
  csv << "name,pipeline,mean_ms,tp,fp,tp_sphere,fp_sphere,frames,speedup_vs_" << reference << "\n";
  md << "| config | pipeline | mean ms / frame | TP | FP | TP (sphere fit) | FP (sphere fit) | "
        "x faster than "
     << reference << " |\n|---|---|---|---|---|---|---|---|\n";
  out << std::fixed << std::setprecision(2);
  for (std::size_t c = 0; c < configs.size(); ++c) {
    const Totals t = Score(trials[c], scenes, 0.08f);
    // Without the reference configuration in the file there is no ratio: left blank.
    std::ostringstream speedup;
    if (reference_ms > 0)
      speedup << std::fixed << std::setprecision(1) << reference_ms / std::max(1e-9, mean_ms[c]);
    const std::string tp_s = sphere_radius ? std::to_string(t.tp_sphere) : "";
    const std::string fp_s = sphere_radius ? std::to_string(t.fp_sphere) : "";
    csv << configs[c].name << ',' << configs[c].PipelineName() << ',' << mean_ms[c] << ',' << t.tp
        << ',' << t.fp << ',' << tp_s << ',' << fp_s << ',' << scenes.size() << ',' << speedup.str()
        << "\n";
    md << "| " << configs[c].name << " | " << configs[c].PipelineName() << " | " << std::fixed
       << std::setprecision(1) << mean_ms[c] << " | " << t.tp << " | " << t.fp << " | "
       << (sphere_radius ? tp_s : "-") << " | " << (sphere_radius ? fp_s : "-") << " | "
       << (reference_ms > 0 ? speedup.str() : "-") << " |\n";
    out << std::setw(10) << configs[c].name << std::setw(10) << configs[c].PipelineName()
        << std::setw(10) << mean_ms[c] << " ms  TP " << t.tp << "  FP " << t.fp;
    if (sphere_radius) out << "  (sphere fit: TP " << t.tp_sphere << "  FP " << t.fp_sphere << ")";
    if (reference_ms > 0) out << "  " << speedup.str() << "x vs " << reference;
    out << "\n";
  }

  // Every trial with the fovea on the truth: which scene found what, and where the time went.
  TextFile tr(dir / "trials.csv");
  tr << "name,scene,ms,tp,fp,points,keypoints,correspondences,hypotheses,instances";
  // Every stage any trial timed, in order (PCL's stock pipeline times fewer stages).
  std::vector<std::string> stage_names;
  for (const auto& per_config : trials)
    for (const Trial& t : per_config)
      for (const auto& [stage, ms] : t.stats.stage_ms)
        if (std::find(stage_names.begin(), stage_names.end(), stage) == stage_names.end())
          stage_names.push_back(stage);
  for (const std::string& stage : stage_names) tr << ",ms_" << stage;
  tr << "\n";
  for (std::size_t c = 0; c < configs.size(); ++c)
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      const Trial& t = trials[c][i];
      const SceneScore s = ScoreScene(t.centres, scenes[i].truth_m, 0.08f);
      tr << configs[c].name << ',' << scenes[i].name << ',' << t.ms << ',' << s.true_positives
         << ',' << s.false_positives << ',' << t.stats.TotalPoints() << ','
         << t.stats.TotalKeypoints() << ',' << t.stats.correspondences << ',' << t.stats.hypotheses
         << ',' << t.centres.size();
      for (const std::string& stage : stage_names) {
        tr << ',';
        for (const auto& [name, ms] : t.stats.stage_ms)
          if (name == stage) tr << ms;
      }
      tr << "\n";
    }

  // Fig. 8 and 9: true and false positives as the distance threshold varies.
  TextFile th(dir / "thresholds.csv");
  th << "name,threshold_m,tp,fp\n";
  for (std::size_t c = 0; c < configs.size(); ++c)
    for (int k = 1; k <= 20; ++k) {
      const Totals t = Score(trials[c], scenes, 0.005f * k);
      th << configs[c].name << ',' << 0.005 * k << ',' << t.tp << ',' << t.fp << "\n";
    }

  // Fig. 10: the fovea moved 0-35 cm from the object along x.
  TextFile sw(dir / "sweep.csv");
  // With attention: scenes found within the loop's budget, mean frames it took them, and the
  // false instances seen on the way.
  sw << "name,offset_m,tp,fp,mean_ms,acquired,mean_frames,acquire_fp\n";
  for (const std::string& name : sweep_names) {
    const auto c = static_cast<std::size_t>(
        std::find_if(configs.begin(), configs.end(),
                     [&](const EvalConfiguration& e) { return e.name == name; }) -
        configs.begin());
    for (std::size_t k = 0; k < sweep_offsets.size(); ++k) {
      const Totals t = Score(swept[c][k], scenes, 0.08f);
      int found = 0, frames = 0, false_instances = 0;
      for (const Acquisition& a : acquired[c][k]) {
        found += a.frames > 0;
        frames += a.frames;
        false_instances += a.false_instances;
      }
      sw << name << ',' << sweep_offsets[k].x() << ',' << t.tp << ',' << t.fp << ','
         << MeanMs(swept[c][k]) << ',' << found << ',' << (found ? double(frames) / found : 0.0)
         << ',' << false_instances << "\n";
    }
  }
  for (const TextFile* file : {&csv, &md, &tr, &th, &sw})
    if (!file->Commit(&error)) return fail(error);

  std::string written = "table.csv table.md trials.csv thresholds.csv sweep.csv";
  if (!args.Has("no-overlays")) {
    const int overlays = WriteCaseOverlays(configs, models, scenes, trials, dir, &error);
    if (overlays < 0) return fail(error);
    if (overlays > 0)
      written += " overlays/ (" + std::to_string(overlays) + " missed or false case(s))";
  }
  if (!args.Has("no-plots")) {
    std::vector<std::string> pngs;
    if (!WritePlots(dir, &pngs, &error))
      return fail(error + "; the CSV and Markdown files are written");
    written += " plot.gp";
    for (const std::string& png : pngs) written += " " + png;
  }
  out << "written to " << dir.string() << "/: " << written << "\n";
  return kExitOk;
}

}  // namespace saccade
