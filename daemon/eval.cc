// `saccade eval`: recognition configurations over a dataset with ground truth, scored with the
// paper's rule (§5.3), written as CSV and Markdown tables and plotted with gnuplot.
#include "attention/attention.h"
#include "core/evaluation.h"
#include "core/fail.h"
#include "core/features.h"
#include "core/opencv_ppf.h"
#include "core/recognition.h"
#include "core/reference_pipeline.h"
#include "core/segmentation.h"
#include "daemon/args.h"
#include "daemon/commands.h"
#include "daemon/eval_report.h"
#include "daemon/tbb_parallel.h"
#include "io/cloud_io.h"
#include "io/config.h"
#include "io/frame_source.h"

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
namespace {

namespace fs = std::filesystem;
using eval::Acquisition;
using eval::EvalModel;
using eval::Scene;
using eval::Trial;

// DIR (a recorded folder: PCD files or depth images) or any source spec.
std::string DatasetSpec(const std::string& dataset) {
  if (dataset.find(':') != std::string::npos) return dataset;
  for (const auto& entry : fs::directory_iterator(dataset))
    if (entry.path().extension() == ".pcd") return "pcd:" + dataset;
  return "depth:" + dataset;
}

double MeanMs(const std::vector<Trial>& trials) {
  double sum = 0;
  for (const Trial& t : trials) sum += t.ms;
  return trials.empty() ? 0 : sum / static_cast<double>(trials.size());
}

// The fovea offsets of the paper's Fig. 10: 0 to 35 cm along x, every 5 cm.
std::vector<Eigen::Vector3f> SweepOffsets() {
  std::vector<Eigen::Vector3f> out;
  for (int cm = 0; cm <= 35; cm += 5) out.emplace_back(0.01f * cm, 0.0f, 0.0f);
  return out;
}

// Protocol (b)'s fovea offset for case i: 15 cm in a random direction, seeded by the case's
// place in the file (uniform on the sphere: a normalized Gaussian triple).
Eigen::Vector3f OffObject(std::size_t i) {
  std::mt19937 rng(1000 + static_cast<unsigned>(i));
  std::normal_distribution<float> n(0, 1);
  Eigen::Vector3f d(n(rng), n(rng), n(rng));
  return 0.15f * d.normalized();
}

class Runner {
 public:
  Runner(const std::vector<EvalModel>& models, ParallelFor parallel, int repeat)
      : models_(models), parallel_(std::move(parallel)), repeat_(repeat) {}

  // Where the fovea is for placement k of scene i (camera frame, metres).
  using FoveaPlacement = std::function<Eigen::Vector3f(std::size_t k, std::size_t i)>;

  // Runs `c` over every scene once per fovea placement (the model is described once); trials
  // come back per placement, then per scene. Each trial is run `repeat` times and the run of
  // median time is kept (recognition is deterministic: only the time differs). With
  // `acquisitions`, each placement also starts the attention loop (Acquire). False with
  // `error` when the model cannot be described.
  bool Run(const EvalConfiguration& c, const std::vector<Scene>& scenes, std::size_t placements,
           const FoveaPlacement& fovea, std::vector<std::vector<Trial>>* trials,
           std::vector<std::vector<Acquisition>>* acquisitions, std::string* error) const {
    trials->assign(placements, {});
    if (acquisitions) acquisitions->assign(placements, {});
    const RecognitionOptions& o = c.config.recognition;
    using Pipeline = EvalConfiguration::Pipeline;
    const bool is_stock = c.pipeline == Pipeline::kStock,
               is_ppf = c.pipeline == Pipeline::kOpencvPpf;
    // ReferenceModel is move-constructible only: built in place.
    std::vector<std::optional<ReferenceModel>> stock(models_.size());
    std::vector<std::optional<ModelDescription>> described(models_.size());
    // OpenCV's PPF models are large (a hash table of every model point pair): one at a time,
    // trained when a scene first needs it.
    std::optional<PpfPeerModel> ppf;
    std::size_t ppf_model = models_.size();
    const PpfPeerOptions ppf_options;
    for (std::size_t m = 0; m < models_.size() && !is_ppf; ++m) {
      if (is_stock) {
        if (auto r = DescribeReferenceModel(models_[m].cloud, o, error))
          stock[m].emplace(std::move(*r));
      } else {
        described[m] = DescribeModel(models_[m].cloud, o, error);
      }
      if (!stock[m] && !described[m]) return false;
    }
    for (std::size_t k = 0; k < placements; ++k) {
      for (std::size_t i = 0; i < scenes.size(); ++i) {
        const Scene& s = scenes[i];
        SceneQuery q;
        q.foveated = c.pipeline == Pipeline::kFoveated;
        q.fovea_m = fovea(k, i);
        q.fovea = c.config.fovea;
        q.intrinsics = s.frame.intrinsics;
        if (is_ppf && ppf_model != s.model) {
          ppf.reset();
          auto trained = TrainPpfPeer(models_[s.model].cloud, ppf_options, error);
          if (!trained) return false;
          ppf.emplace(std::move(*trained));
          ppf_model = s.model;
        }
        std::vector<Trial> runs;
        for (int run = 0; run < repeat_; ++run) {
          const auto t0 = std::chrono::steady_clock::now();
          const RecognitionResult r =
              is_stock ? RecognizeReference(*stock[s.model], *s.frame.cloud, o)
              : is_ppf ? RecognizePpfPeer(*ppf, *s.frame.cloud, ppf_options)
                       : Recognize(*described[s.model], *s.frame.cloud, q, o, parallel_);
          Trial t;
          t.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                     .count();
          t.centres = Centres(r, s);
          t.stats = r.stats;
          if (run == 0) t.evidence = Evidence(r, s, described[s.model], o);
          for (const Detection& d : r.instances) {
            t.instances.push_back(d);
            t.instances.back().correspondences.clear();
          }
          runs.push_back(std::move(t));
        }
        const CaseEvidence evidence = runs.front().evidence;
        auto median = runs.begin() + runs.size() / 2;
        std::nth_element(runs.begin(), median, runs.end(),
                         [](const Trial& a, const Trial& b) { return a.ms < b.ms; });
        if (acquisitions && described[s.model])
          (*acquisitions)[k].push_back(Acquire(*described[s.model], s, q, o, median->centres));
        median->evidence = evidence;
        (*trials)[k].push_back(std::move(*median));
      }
    }
    return true;
  }

 private:
  // Each instance's scored point (the model's centre) in the scene.
  std::vector<Eigen::Vector3f> Centres(const RecognitionResult& r, const Scene& s) const {
    std::vector<Eigen::Vector3f> out;
    for (const Detection& d : r.instances)
      out.push_back((d.model_to_scene * models_[s.model].centre.homogeneous()).head<3>());
    return out;
  }

  // What the truth says of a run: matches the true pose explains (within a Hough bin of the
  // model's fitted radii), and verification's verdicts on the hypotheses near the truth.
  // `model` is the description recognition used (nullopt for the peers, which report no matches).
  CaseEvidence Evidence(const RecognitionResult& r, const Scene& s,
                        const std::optional<ModelDescription>& model,
                        const RecognitionOptions& given) const {
    CaseEvidence e;
    const EvalModel& m = models_[s.model];
    const Cloud& scene = *s.frame.cloud;
    if (r.correspondences.empty() && r.stats.correspondences > 0) {
      e.correct_correspondences = -1;  // matched, but the pipeline does not say what
    } else if (s.truth_pose) {
      const float tolerance =
          std::max(0.02f, model ? RadiiForModel(given, model->scale()).hough_bin_m : 0.0f);
      for (const auto& [mi, si] : r.correspondences) {
        const Eigen::Vector3f p =
            (*s.truth_pose * m.cloud[mi].getVector3fMap().homogeneous()).head<3>();
        e.correct_correspondences += (p - scene[si].getVector3fMap()).norm() <= tolerance;
      }
    }
    for (std::size_t h = 0; h < r.hypotheses.size(); ++h) {
      const Eigen::Vector3f centre =
          (r.hypotheses[h].model_to_scene * m.centre.homogeneous()).head<3>();
      if ((centre - s.truth_m).norm() > 0.08f) continue;
      e.true_hypotheses.push_back(h < r.verdicts.size() ? r.verdicts[h] : Verdict::kKept);
    }
    e.found = ScoreScene(Centres(r, s), s.truth_m, 0.08f).true_positives > 0;
    return e;
  }

  // The daemon's attention loop (AttentionOptions' defaults: G grows by 0.1 m a lost frame to
  // 1 m) started with the fovea where `q` puts it, on the same frame again and again, as a
  // robot that has lost a still object: the fovea follows what is detected and grows while
  // nothing is; past G_max (FULL_SCAN) it recognizes in the whole frame, as the daemon does. It
  // gives up after a second's worth of frames (it may be following something false). `first`
  // is what the trial from `q` found: the loop's first frame when its fovea is the same.
  Acquisition Acquire(const ModelDescription& model, const Scene& s, SceneQuery q,
                      const RecognitionOptions& o,
                      const std::vector<Eigen::Vector3f>& first) const {
    constexpr int kMaxFrames = 30;
    Acquisition a;
    Attention attention(AttentionOptions{}, q.fovea_m);
    const bool foveated = q.foveated;
    for (int frame = 1; frame <= kMaxFrames; ++frame) {
      const Fixation& f = attention.current();
      const Eigen::Vector3f growth = Eigen::Vector3f::Constant(f.growth_m);
      const bool as_trial = frame == 1 && q.fovea.growth_m == growth;  // fovea_m is q's too
      q.fovea_m = f.fovea_m;
      q.fovea.growth_m = growth;
      q.foveated = foveated && f.mode != AttentionMode::kFullScan;  // past G_max: the whole frame
      const std::vector<Eigen::Vector3f> centres =
          as_trial ? first : Centres(Recognize(model, *s.frame.cloud, q, o, parallel_), s);
      std::vector<Detection> sightings;
      bool found = false;
      for (const Eigen::Vector3f& centre : centres) {
        sightings.emplace_back().centroid_m = centre;
        sightings.back().model = 0;
        if ((centre - s.truth_m).norm() <= 0.08f)
          found = true;
        else
          ++a.false_instances;
      }
      if (found) {
        a.frames = frame;
        break;
      }
      attention.Update(frame, frame / 30.0, sightings);
    }
    return a;
  }

  const std::vector<EvalModel>& models_;
  const ParallelFor parallel_;
  const int repeat_;
};

struct Totals {
  int tp = 0, fp = 0, tp_sphere = 0, fp_sphere = 0;
};

Totals Score(const std::vector<Trial>& trials, const std::vector<Scene>& scenes, float threshold) {
  Totals t;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const SceneScore s = ScoreScene(trials[i].centres, scenes[i].truth_m, threshold);
    t.tp += s.true_positives;
    t.fp += s.false_positives;
    if (scenes[i].sphere_truth_m) {
      const SceneScore f = ScoreScene(trials[i].centres, *scenes[i].sphere_truth_m, threshold);
      t.tp_sphere += f.true_positives;
      t.fp_sphere += f.false_positives;
    }
  }
  return t;
}

// The scene category of each case (by name) from the cases.csv beside a cases file, when there
// is one with `name` and `scene_category` columns (the mOSD benchmark's); empty otherwise.
std::map<std::string, std::string> CaseCategories(const std::string& cases_path) {
  std::map<std::string, std::string> out;
  std::ifstream in(fs::path(cases_path).parent_path() / "cases.csv");
  std::string line;
  if (!std::getline(in, line)) return out;
  const auto split = [](std::string l) {
    if (!l.empty() && l.back() == '\r') l.pop_back();  // the benchmark's file has CRLF lines
    std::vector<std::string> cells;
    std::stringstream ss(l);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    return cells;
  };
  const std::vector<std::string> header = split(line);
  const auto column = [&](const char* name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t name = column("name"), category = column("scene_category");
  if (name >= header.size() || category >= header.size()) return out;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    if (cells.size() == header.size()) out[cells[name]] = cells[category];
  }
  return out;
}

// Each case's model (its object's labelled points, in the camera frame of its capture) and scene
// (the other capture, with the centroid of the object's labelled points as the truth).
// With `only` non-empty, just the cases it names (each must exist); of those, every `every`-th.
bool LoadCaseScenes(const std::string& path, const std::string& data_dir,
                    const std::vector<std::string>& only, int every, std::vector<EvalModel>* models,
                    std::vector<Scene>* scenes, std::string* error) {
  std::vector<LabelledCase> cases;
  if (!LoadLabelledCases(path, data_dir, &cases, error)) return false;
  if (every > 1) {
    std::vector<LabelledCase> kept;
    for (std::size_t i = 0; i < cases.size(); i += std::size_t(every)) kept.push_back(cases[i]);
    cases.swap(kept);
  }
  if (!only.empty()) {
    for (const std::string& name : only)
      if (std::none_of(cases.begin(), cases.end(),
                       [&](const LabelledCase& c) { return c.name == name; }))
        return Fail(error, path + ": --only: no case named '" + name + "'");
    cases.erase(std::remove_if(cases.begin(), cases.end(),
                               [&](const LabelledCase& c) {
                                 return std::find(only.begin(), only.end(), c.name) == only.end();
                               }),
                cases.end());
  }
  if (cases.empty()) return Fail(error, path + ": no cases");
  const std::map<std::string, std::string> categories = CaseCategories(path);
  // Each capture is loaded once; cases searching the same capture share its cloud.
  struct Capture {
    std::shared_ptr<const Cloud> cloud;
    std::vector<std::uint32_t> labels;
    CameraIntrinsics intrinsics;
  };
  std::map<std::string, Capture> loaded;
  const auto load = [&](const std::string& file) -> const Capture* {
    auto it = loaded.find(file);
    if (it == loaded.end()) {
      auto labelled = LoadLabelledCloud(file, error);
      if (!labelled) return nullptr;
      Capture c;
      if (const auto k = EstimateIntrinsics(labelled->cloud)) c.intrinsics = *k;
      c.cloud = std::make_shared<const Cloud>(std::move(labelled->cloud));
      c.labels = std::move(labelled->labels);
      it = loaded.emplace(file, std::move(c)).first;
    }
    return &it->second;
  };
  // The finite points of object k (mOSD labels 10k..10k+9), as a cloud; an error when none.
  const auto object = [&](const LabelledCase& c, const std::string& file, const Capture& capture,
                          int k) -> std::optional<Cloud> {
    std::vector<int> points;
    for (std::size_t i = 0; i < capture.labels.size(); ++i)
      if (capture.labels[i] >= 10 && int(capture.labels[i] / 10) == k &&
          (*capture.cloud)[i].getVector3fMap().allFinite())
        points.push_back(int(i));
    if (points.empty()) {
      Fail(error, path + ": case " + c.name + ": " + file + " has no object " + std::to_string(k));
      return std::nullopt;
    }
    return ExtractPoints(*capture.cloud, points);
  };
  for (const LabelledCase& c : cases) {
    const Capture* source = load(c.model_file);
    const Capture* target = source ? load(c.scene_file) : nullptr;
    if (!target) return false;
    auto model = object(c, c.model_file, *source, c.model_object);
    const auto truth = model ? object(c, c.scene_file, *target, c.scene_object) : std::nullopt;
    if (!truth) return false;
    Scene s;
    s.truth_m = *FiniteCentroid(*truth);
    s.truth_pose = c.truth_pose;
    s.feasible = c.feasible;
    s.identity = c.identity.empty() ? c.name.substr(0, c.name.find('-')) : c.identity;
    if (const auto it = categories.find(c.name); c.category.empty() && it != categories.end())
      s.category = it->second;
    else
      s.category = c.category;
    s.frame.cloud = target->cloud;
    s.frame.intrinsics = target->intrinsics;
    s.frame.sequence = scenes->size();
    s.model = models->size();
    s.name = c.name;
    const Eigen::Vector3f centre = *FiniteCentroid(*model);
    models->push_back({std::move(*model), centre});
    scenes->push_back(std::move(s));
  }
  return true;
}

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
  models->push_back({std::move(*model), *model_centre});
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

}  // namespace

int RunEval(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args;
  std::string error;
  if (!args.Parse(argv,
                  {"dataset", "model", "configs", "out", "model-centre", "sphere-radius",
                   "reference", "frames", "sweep", "truth-pose", "cases", "data", "repeat",
                   "protocols", "only", "every"},
                  {"no-plots"}, &error))
    return Usage(err, "eval", error);
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
  if (!LoadEvalConfigurations(args.Get("configs"), RecognitionConfig{}, &configs, &error))
    return fail(error);
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

  if (!cases && (args.Has("protocols") || args.Has("only") || args.Has("every")))
    return Usage(err, "eval", "--protocols, --only and --every apply to --cases only");
  std::vector<eval::Protocol> protocols;  // --cases only
  for (const std::string& p : Args::ParseList(args.Get("protocols", cases ? "a" : ""))) {
    if (p.size() != 1 || p[0] < 'a' || p[0] > 'c')
      return Usage(err, "eval", "--protocols expects a list of a, b, c (e.g. a,b,c)");
    protocols.push_back(eval::Protocol(p[0] - 'a'));
  }

  std::vector<EvalModel> models;
  std::vector<Scene> scenes;
  if (cases) {
    const std::vector<std::string> only = Args::ParseList(args.Get("only"));
    const auto every = Args::ParsePositiveInt(args.Get("every", "1"));
    if (!every) return Usage(err, "eval", "--every expects a positive integer");
    if (!LoadCaseScenes(args.Get("cases"), args.Get("data", "../shared/data"), only, *every,
                        &models, &scenes, &error))
      return fail(error);
  } else if (auto code =
                 LoadDatasetScenes(args, sphere_radius, max_frames, &models, &scenes, err)) {
    return *code;
  }

  const fs::path dir = args.Get("out", "eval-out");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return fail(dir.string() + ": cannot create it (" + ec.message() + ")");
  Runner runner(models, MakeTbbParallelFor(), *repeat);
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
    if (!runner.Run(
            configs[c], scenes, sweep ? sweep_offsets.size() : 1,
            [&](std::size_t k, std::size_t i) { return scenes[i].truth_m + sweep_offsets[k]; },
            &per_offset, sweep ? &acquired[c] : nullptr, &error))
      return fail("configuration " + configs[c].name + ": " + error);
    trials[c] = per_offset.front();
    mean_ms[c] = MeanMs(trials[c]);
    if (sweep) swept[c] = std::move(per_offset);
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
        if (p == eval::Protocol::kOnObject) {
          run.trials = trials[c];
        } else if (!runner.Run(
                       configs[c], scenes, 1,
                       [&](std::size_t, std::size_t i) {
                         return acquire ? Eigen::Vector3f(0, 0, 1)
                                        : scenes[i].truth_m + OffObject(i);
                       },
                       &per, acquire ? &acquisitions : nullptr, &error)) {
          return fail("configuration " + configs[c].name + ": " + error);
        } else {
          run.trials = std::move(per.front());
          if (acquire) run.acquisitions = std::move(acquisitions.front());
        }
        runs[c].push_back(std::move(run));
        err << "saccade eval: configuration " << configs[c].name << ", protocol "
            << eval::ProtocolName(p) << " done\n";
      }
    eval::WriteCaseReport(args.Get("cases"), configs, models, scenes, runs, dir, out);
  }
  const std::string reference = args.Get("reference", "10");
  double reference_ms = 0;
  for (std::size_t c = 0; c < configs.size(); ++c)
    if (configs[c].name == reference) reference_ms = mean_ms[c];

  // Table 7.
  std::ofstream csv(dir / "table.csv"), md(dir / "table.md");
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
  std::ofstream tr(dir / "trials.csv");
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
  std::ofstream th(dir / "thresholds.csv");
  th << "name,threshold_m,tp,fp\n";
  for (std::size_t c = 0; c < configs.size(); ++c)
    for (int k = 1; k <= 20; ++k) {
      const Totals t = Score(trials[c], scenes, 0.005f * k);
      th << configs[c].name << ',' << 0.005 * k << ',' << t.tp << ',' << t.fp << "\n";
    }

  // Fig. 10: the fovea moved 0-35 cm from the object along x.
  std::ofstream sw(dir / "sweep.csv");
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
  csv.close(), md.close(), tr.close(), th.close(), sw.close();

  if (!args.Has("no-plots")) {
    std::string names, swept;
    for (const auto& c : configs) names += c.name + " ";
    for (const auto& n : sweep_names) swept += n + " ";
    // The script is left beside the data, to restyle the plots by hand.
    std::ofstream gp(dir / "plot.gp");
    gp << "# gnuplot script written by saccade eval; run: gnuplot plot.gp (in this folder)\n"
       << "set datafile separator ','\nset terminal pngcairo size 900,600\nset grid\n"
       << "set key outside right\nnames = '" << names << "'\nswept = '" << swept << "'\n"
       << "set xlabel 'distance threshold (cm)'\n"
       << "set output 'thresholds_tp.png'\nset ylabel 'true positives'\n"
       << "plot for [n in names] 'thresholds.csv' using ($2*100):(strcol(1) eq n ? $3 : 1/0) "
          "with linespoints title n\n"
       << "set output 'thresholds_fp.png'\nset ylabel 'false positives'\n"
       << "plot for [n in names] 'thresholds.csv' using ($2*100):(strcol(1) eq n ? $4 : 1/0) "
          "with linespoints title n\n"
       << "set output 'sweep.png'\nset xlabel 'fovea distance from the object (cm)'\n"
       << "set ylabel 'true positives'\n"
       << "if (strlen(swept) > 0) { plot for [n in swept] 'sweep.csv' using ($2*100):"
          "(strcol(1) eq n ? $3 : 1/0) with linespoints title n } else { "
          "set xrange [0:35]; set yrange [0:1]; set label 'no sweep (--sweep)' at graph 0.4,0.5;"
          " plot 2 notitle }\n"
       << "set output 'sweep_attention.png'\n"
       << "set ylabel 'frames until found, attention loop (mean over scenes found)'\n"
       << "if (strlen(swept) > 0) { plot for [n in swept] 'sweep.csv' using ($2*100):"
          "(strcol(1) eq n && $6 > 0 ? $7 : 1/0) with linespoints title n } else { "
          "plot 2 notitle }\n";
    gp.close();
    const std::string command = "cd '" + dir.string() + "' && gnuplot plot.gp 2> plot.log";
    if (std::system(command.c_str()) != 0)
      return fail("gnuplot failed (see " + (dir / "plot.log").string() +
                  "); the CSV and Markdown files are written");
  }
  out << "written to " << dir.string()
      << "/: table.csv table.md trials.csv thresholds.csv sweep.csv"
      << (args.Has("no-plots")
              ? ""
              : " thresholds_tp.png thresholds_fp.png sweep.png sweep_attention.png")
      << "\n";
  return kExitOk;
}

}  // namespace saccade
