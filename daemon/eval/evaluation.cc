#include "daemon/eval/evaluation.h"

#include "attention/attention.h"
#include "core/eval/opencv_ppf.h"
#include "core/eval/reference_pipeline.h"
#include "core/fail.h"
#include "core/features.h"
#include "core/segmentation.h"
#include "core/sim/rerender.h"
#include "daemon/eval/other_captures.h"
#include "daemon/eval/texture.h"
#include "io/formats/cloud_io.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

namespace saccade::eval {

namespace fs = std::filesystem;

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

Eigen::Vector3f EvalModel::ScoredPoint(const Eigen::Matrix4f& model_to_scene) const {
  const Eigen::Matrix3f r = model_to_scene.topLeftCorner<3, 3>();
  const Eigen::Vector3f t = model_to_scene.topRightCorner<3, 1>();
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  int n = 0;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const Eigen::Vector3f p = r * sample[i] + t;
    if ((r * sample_normals[i]).dot(-p) <= 0) continue;  // turned away from the camera
    sum += p;
    ++n;
  }
  return n ? Eigen::Vector3f(sum / float(n)) : Eigen::Vector3f(r * centre + t);
}

EvalModel ViewsEvalModel(std::vector<Cloud> views) {
  EvalModel m;
  for (const Cloud& view : views) {
    const std::vector<std::uint8_t> mask(view.size(), 1);
    const Normals normals = KnnNormals(view, mask, 10);
    Cloud& kept = m.views.emplace_back();
    for (std::size_t i = 0; i < view.size(); ++i) {
      if (!FinitePoint(view[i])) continue;
      m.cloud.push_back(view[i]);
      kept.push_back(view[i]);
      if (i % 8 || !normals[i].allFinite()) continue;
      m.sample.push_back(view[i].getVector3fMap());
      m.sample_normals.push_back(normals[i]);
    }
    // Only its finite points and its sensor are described (DescribeModel): a capture's whole
    // organized frame, NaN outside the object, would hold ~10 MB a view for every case.
    kept.sensor_origin_ = view.sensor_origin_;
    kept.sensor_orientation_ = view.sensor_orientation_;
  }
  if (const auto c = FiniteCentroid(m.cloud)) m.centre = *c;
  return m;
}

Runner::Runner(const std::vector<EvalModel>& models, ParallelFor parallel, int repeat)
    : models_(models), parallel_(std::move(parallel)), repeat_(repeat) {}

bool Runner::Run(const EvalConfiguration& c, const std::vector<Scene>& scenes,
                 std::size_t placements, const FoveaPlacement& fovea,
                 std::vector<std::vector<Trial>>* trials,
                 std::vector<std::vector<Acquisition>>* acquisitions, std::string* error,
                 const SearchOptions& search) const {
  trials->assign(placements, {});
  if (acquisitions) acquisitions->assign(placements, {});
  const RecognitionOptions& o = c.config.recognition;
  using Pipeline = EvalConfiguration::Pipeline;
  const bool is_stock = c.pipeline == Pipeline::kStock, is_ppf = c.pipeline == Pipeline::kOpencvPpf;
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
      described[m] = models_[m].views.empty() ? DescribeModel(models_[m].cloud, o, error)
                                              : DescribeModel(models_[m].views, o, error);
    }
    if (!stock[m] && !described[m]) return false;
  }
  // The scene's whole-frame candidates, when a given fovea lands on one or protocol (c) visits
  // them: proposed once per scene (it is the same every frame), with what proposing cost.
  const bool lands = search.attention.land_on_candidate_m > 0;
  const bool visits = acquisitions && search.attention.search == SearchKind::kCandidates;
  std::vector<ModelSignature> signatures(models_.size());
  for (std::size_t m = 0; m < models_.size(); ++m)
    if (described[m] && (lands || visits)) signatures[m] = SignModel(*described[m]);
  const auto propose = [&](const Scene& s) {
    Proposed p;
    if (signatures[s.model].radius_m <= 0) return p;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Candidate& c : ProposeCandidates(*s.frame.cloud, s.frame.intrinsics,
                                                signatures[s.model], search.candidates))
      p.places.push_back(c.centre_m);
    p.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return p;
  };
  for (std::size_t k = 0; k < placements; ++k) {
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      const Scene& s = scenes[i];
      SceneQuery q;
      q.foveated = c.pipeline == Pipeline::kFoveated;
      const Proposed proposed = q.foveated ? propose(s) : Proposed{};
      const double landing_ms = lands ? proposed.ms : 0;
      q.fovea_m = lands && q.foveated ? LandOnCandidate(fovea(k, i), proposed.places,
                                                        search.attention.land_on_candidate_m,
                                                        search.attention.land_stay_m)
                                      : fovea(k, i);
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
        t.ms = landing_ms +
               std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
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
      if (texture_ && !runs.empty()) {
        constexpr float kTextureToleranceM = 0.02f;
        const TextureView scene_view(*s.frame.cloud, s.frame.intrinsics, 1000);
        const TextureView model_view(models_[s.model].cloud, s.frame.intrinsics, 500);
        const auto matches = scene_view.Match(model_view);
        for (Trial& t : runs) {
          t.texture.clear();
          for (const Detection& d : t.instances)
            t.texture.push_back(TextureSupport(matches, d.model_to_scene, kTextureToleranceM));
        }
      }
      const CaseEvidence evidence = runs.front().evidence;
      auto median = runs.begin() + runs.size() / 2;
      std::nth_element(runs.begin(), median, runs.end(),
                       [](const Trial& a, const Trial& b) { return a.ms < b.ms; });
      if (acquisitions && described[s.model])
        (*acquisitions)[k].push_back(Acquire(*described[s.model], s, fovea(k, i), q, o, search,
                                             proposed, median->instances));
      median->evidence = evidence;
      (*trials)[k].push_back(std::move(*median));
      if (tick_) tick_(k * scenes.size() + i + 1, placements * scenes.size());
    }
  }
  return true;
}

std::vector<Eigen::Vector3f> Runner::Centres(const RecognitionResult& r, const Scene& s) const {
  std::vector<Eigen::Vector3f> out;
  for (const Detection& d : r.instances)
    out.push_back(models_[s.model].ScoredPoint(d.model_to_scene));
  return out;
}

CaseEvidence Runner::Evidence(const RecognitionResult& r, const Scene& s,
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
    const Eigen::Vector3f centre = m.ScoredPoint(r.hypotheses[h].model_to_scene);
    if ((centre - s.truth_m).norm() > 0.08f) continue;
    e.true_hypotheses.push_back(h < r.verdicts.size() ? r.verdicts[h] : Verdict::kKept);
  }
  e.found = ScoreScene(Centres(r, s), s.truth_m, 0.08f).true_positives > 0;
  return e;
}

Acquisition Runner::Acquire(const ModelDescription& model, const Scene& s,
                            const Eigen::Vector3f& aim_m, SceneQuery q, const RecognitionOptions& o,
                            const SearchOptions& search, const Proposed& proposed,
                            const std::vector<Detection>& first) const {
  constexpr int kMaxFrames = 30;
  Acquisition a;
  // Given the fovea `aim_m`, the first frame was recognized where it landed (q.fovea_m), as
  // saccaded lands a given fovea in the frame it is given for.
  Attention attention(search.attention, aim_m);
  attention.Landed(aim_m, q.fovea_m);
  const bool foveated = q.foveated;
  // The scene is the same every frame: its candidates were proposed once, and their cost is
  // counted in every frame that searches (saccaded proposes them on each search frame).
  const bool visits = search.attention.search == SearchKind::kCandidates;
  const std::vector<Eigen::Vector3f> none;
  const std::vector<Eigen::Vector3f>& places = visits ? proposed.places : none;
  const double candidates_ms = visits ? proposed.ms : 0;
  for (std::size_t r = 0; r < places.size() && a.candidate_rank < 0; ++r)
    if ((places[r] - s.truth_m).norm() <= 0.1f) a.candidate_rank = int(r);
  const EvalModel& m = models_[s.model];
  for (int frame = 1; frame <= kMaxFrames; ++frame) {
    const Fixation& f = attention.current();
    const Eigen::Vector3f growth = Eigen::Vector3f::Constant(f.growth_m);
    const bool as_trial = frame == 1 && q.fovea.growth_m == growth;  // fovea_m is q's too
    q.fovea_m = f.fovea_m;
    q.fovea.growth_m = growth;
    q.foveated = foveated && f.mode != AttentionMode::kFullScan;  // past G_max: the whole frame
    q.search_phase = f.SearchPhase();  // as saccaded walks a budgeted search
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Detection> sightings;
    const auto sight = [&](const std::vector<Detection>& instances, std::vector<Detection>* found) {
      for (const Detection& d : instances) {
        Detection& seen = found->emplace_back();
        seen.centroid_m = m.ScoredPoint(d.model_to_scene);
        seen.confidence = d.confidence;
        seen.model = 0;
      }
    };
    sight(as_trial ? first : Recognize(model, *s.frame.cloud, q, o, parallel_).instances,
          &sightings);
    // Further looks in this frame, as saccaded takes them (attention.looks_per_frame).
    const std::vector<Eigen::Vector3f> looks = attention.PlanLooks().Take(
        q.fovea_m, places, &sightings,
        [&](const Eigen::Vector3f& place, std::vector<Detection>* found) {
          SceneQuery look = q;
          look.fovea_m = place;
          look.search_phase = 0;
          sight(Recognize(model, *s.frame.cloud, look, o, parallel_).instances, found);
        });
    attention.Looked(attention.current().frame_seq, q.fovea_m, looks);
    a.frame_ms.push_back(
        candidates_ms +
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    for (const Detection& seen : sightings)
      a.false_instances += (seen.centroid_m - s.truth_m).norm() > 0.08f;
    const int before = attention.current().target;
    const Fixation& next = attention.Update(frame, frame / 30.0, sightings, places);
    if (next.mode != AttentionMode::kTracking) continue;
    if (a.first_lock_frame == 0) a.first_lock_frame = frame, a.first_lock_why = next.reason;
    // Attention follows a target: the truth, or a lock onto a false instance (counted once per
    // target, or again when a challenge moved it).
    if ((next.fovea_m - s.truth_m).norm() <= 0.08f) {
      a.frames = frame;
      break;
    }
    if (next.target != before || next.reason.rfind("challenged", 0) == 0) ++a.false_locks;
  }
  return a;
}

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
                    std::vector<Scene>* scenes, std::string* error, const CaseModels& case_models) {
  std::vector<LabelledCase> cases;
  if (!LoadLabelledCases(path, data_dir, &cases, error)) return false;
  const std::vector<LabelledCase> all = cases;
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
  // Each capture is loaded once, and each object cut once (other captures: every model
  // shares them).
  CaptureCuts captures(path);
  const auto load = [&](const std::string& file) { return captures.Load(file, error); };
  const auto cut = [&](const CaptureKey& key) { return captures.Cut(key, error); };
  std::optional<OtherCaptureModels> others;
  if (case_models.other_captures)
    others.emplace(all, AlignmentOptions{}, cut, case_models.parallel, case_models.log);
  std::map<std::pair<std::string, CaptureKey>, std::size_t> model_of;  // (identity, scene)
  std::map<std::size_t, std::optional<Eigen::Matrix4f>> truth_of;      // per model
  for (const LabelledCase& c : cases) {
    const CaptureKey scene_key{c.scene_file, c.scene_object};
    const Cloud* model = cut({c.model_file, c.model_object});
    const Cloud* truth = model ? cut(scene_key) : nullptr;
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
    const CaptureCuts::Capture* target = load(c.scene_file);
    s.frame.cloud = target->cloud;
    s.frame.intrinsics = target->intrinsics;
    s.frame.sequence = scenes->size();
    s.name = c.name;
    if (others) {
      const auto key = std::make_pair(s.identity, scene_key);
      auto it = model_of.find(key);
      if (it == model_of.end()) {
        auto views = others->For(s.identity, scene_key, error);
        if (!views) return Fail(error, path + ": case " + c.name + ": " + *error);
        it = model_of.emplace(key, models->size()).first;
        models->push_back(ViewsEvalModel(std::move(views->views)));
        if (case_models.log)
          *case_models.log << "  " << c.scene_file << " object " << c.scene_object << ": "
                           << models->back().views.size() << " views from "
                           << views->reference.first
                           << (views->left_out
                                   ? ", " + std::to_string(views->left_out) + " not aligned"
                                   : "")
                           << (views->truth_pose ? "" : ", no truth pose") << "\n";
        truth_of[it->second] = views->truth_pose;
      }
      s.model = it->second;
      s.truth_pose = truth_of[it->second];
    } else {
      s.model = models->size();
      EvalModel& m = models->emplace_back();
      std::vector<int> finite;
      for (std::size_t i = 0; i < model->size(); ++i)
        if (FinitePoint((*model)[i])) finite.push_back(int(i));
      m.cloud = ExtractPoints(*model, finite);
      m.centre = *FiniteCentroid(*model);
    }
    scenes->push_back(std::move(s));
  }
  return true;
}

}  // namespace saccade::eval
