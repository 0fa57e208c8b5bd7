// The evaluation harness behind `saccade eval`: datasets and cross-capture cases with their
// truth, configurations run over them (our pipelines and the peers), protocol (c)'s attention
// loop, and the scores. daemon/cli/eval_command.cc is the thin command around it;
// daemon/eval/report.h writes the cross-capture report.
#pragma once

#include "attention/attention.h"
#include "core/candidates.h"
#include "core/eval/evaluation.h"
#include "core/parallel.h"
#include "core/recognition.h"
#include "io/config/config.h"
#include "io/sources/frame_source.h"

#include <Eigen/Core>

#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace saccade::eval {

/// One frame of the dataset and what is true of it.
struct Scene {
  Frame frame;
  Eigen::Vector3f truth_m = Eigen::Vector3f::Zero();  // the generator's (or recording's) centre
  std::optional<Eigen::Vector3f> sphere_truth_m;      // the RANSAC sphere fit's centre
  std::size_t model = 0;                              // which model is searched in it
  std::string name;                                   // the case's name, or the frame number
  /// Cases only (eval --cases): the truth pose (model capture to scene capture), whether any
  /// pose can be verified at all, and what the case is of.
  std::optional<Eigen::Matrix4f> truth_pose;
  bool feasible = true;
  std::string identity, category;
};

/// A model and the point of it whose place in the scene is scored.
struct EvalModel {
  Cloud cloud;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  /// A model of several captures (eval --model-source other-captures): its views (each its
  /// finite points and sensor origin), described together, and a sample of its points with their
  /// normals (facing their sensor). Such a model is scored at the centroid of the points its pose
  /// turns towards the camera, the side a scene's labelled points show, instead of at `centre`.
  std::vector<Cloud> views;
  std::vector<Eigen::Vector3f> sample, sample_normals;
  /// Where the scored point of the model lands under `model_to_scene`.
  Eigen::Vector3f ScoredPoint(const Eigen::Matrix4f& model_to_scene) const;
};

/// A model of `views` (each in the model frame with its sensor origin), scored on its visible
/// side.
EvalModel ViewsEvalModel(std::vector<Cloud> views);

/// What one configuration found in one frame with the fovea at one place.
struct Trial {
  double ms = 0;
  std::vector<Eigen::Vector3f> centres;  // each instance's model centre in the scene
  std::vector<Detection> instances;      // as reported, best first (correspondences dropped)
  RecognitionStats stats;
  CaseEvidence evidence;     // what the truth says of this run's stages
  std::vector<int> texture;  // per instance: its texture support (Runner::MeasureTexture), or empty
};

/// The attention loop's run from one fovea: frames until attention locks onto (follows) an
/// instance within 8 cm of the truth (0: not before it gave up), the locks onto a false
/// instance before that, the false instances it saw on the way, where the truth ranked among
/// the frame's candidates, and each frame's search cost (candidates and recognition).
struct Acquisition {
  int frames = 0;
  int false_locks = 0;
  int false_instances = 0;
  int candidate_rank = -1;     // the first candidate within 10 cm of the truth, -1 when none
  int first_lock_frame = 0;    // the frame attention first followed a target (0: never)
  std::string first_lock_why;  // and why: detected, tentative, challenged
  std::vector<double> frame_ms;
};

/// A scene's whole-frame candidates, best first, and what proposing them cost.
struct Proposed {
  std::vector<Eigen::Vector3f> places;
  double ms = 0;
};

/// How the attention loop searches in protocol (c): the attention options and the whole-frame
/// candidates' (an evaluation configuration's `attention` and `candidates` sections).
struct SearchOptions {
  AttentionOptions attention;
  CandidateOptions candidates;
};

/// The three protocols of the cross-capture benchmark.
enum class Protocol {
  kOnObject,     // (a) the fovea on the object's centroid, one frame
  kOffObject,    // (b) one frame, the fovea 15 cm from it in a seeded random direction
  kAcquisition,  // (c) the attention loop from (0, 0, 1) m, the scene repeated as frames
};
const char* ProtocolName(Protocol p);  // "a" / "b" / "c"

/// One configuration under one protocol, over every case.
struct ProtocolRun {
  Protocol protocol = Protocol::kOnObject;
  std::vector<Trial> trials;              // per scene (protocol c: the loop's first frame)
  std::vector<Acquisition> acquisitions;  // per scene, protocol c only
};

/// DIR (a recorded folder: PCD files or depth images) or any source spec, as a source spec.
std::string DatasetSpec(const std::string& dataset);
/// The trials' mean time, ms (0 when there are none).
double MeanMs(const std::vector<Trial>& trials);
/// The fovea offsets of the paper's Fig. 10: 0 to 35 cm along x, every 5 cm.
std::vector<Eigen::Vector3f> SweepOffsets();
/// Protocol (b)'s fovea offset for case i: 15 cm in a random direction seeded by i.
Eigen::Vector3f OffObject(std::size_t i);

/// Runs configurations over scenes. Thread-compatible; each Run uses `parallel` inside.
class Runner {
 public:
  /// `models` outlive the runner; each trial is run `repeat` times (>= 1).
  Runner(const std::vector<EvalModel>& models, ParallelFor parallel, int repeat);
  /// Also measure each instance's texture support (daemon/eval/texture.h), untimed.
  void MeasureTexture(bool on) { texture_ = on; }
  /// Called after each scene of a Run with the scenes done and to do (placements x scenes).
  using Tick = std::function<void(std::size_t done, std::size_t total)>;
  void Report(Tick tick) { tick_ = std::move(tick); }

  /// Where the fovea is for placement k of scene i (camera frame, metres).
  using FoveaPlacement = std::function<Eigen::Vector3f(std::size_t k, std::size_t i)>;

  /// Runs `c` over every scene once per fovea placement (the model is described once); trials
  /// come back per placement, then per scene. Each trial is run `repeat` times and the run of
  /// median time is kept (recognition is deterministic: only the time differs). With
  /// `acquisitions`, each placement also starts the attention loop (protocol c). False with
  /// `error` when the model cannot be described.
  bool Run(const EvalConfiguration& c, const std::vector<Scene>& scenes, std::size_t placements,
           const FoveaPlacement& fovea, std::vector<std::vector<Trial>>* trials,
           std::vector<std::vector<Acquisition>>* acquisitions, std::string* error,
           const SearchOptions& search = {}) const;

 private:
  std::vector<Eigen::Vector3f> Centres(const RecognitionResult& r, const Scene& s) const;
  CaseEvidence Evidence(const RecognitionResult& r, const Scene& s,
                        const std::optional<ModelDescription>& model,
                        const RecognitionOptions& given) const;
  Acquisition Acquire(const ModelDescription& model, const Scene& s, const Eigen::Vector3f& aim_m,
                      SceneQuery q, const RecognitionOptions& o, const SearchOptions& search,
                      const Proposed& proposed, const std::vector<Detection>& first) const;

  const std::vector<EvalModel>& models_;
  const ParallelFor parallel_;
  const int repeat_;
  bool texture_ = false;
  Tick tick_;
};

/// True and false positives of the trials over the scenes at `threshold` metres, against the
/// truth and (when scenes have one) the sphere fit.
struct Totals {
  int tp = 0, fp = 0, tp_sphere = 0, fp_sphere = 0;
};
Totals Score(const std::vector<Trial>& trials, const std::vector<Scene>& scenes, float threshold);

/// The scene category of each case (by name) from the cases.csv beside a cases file, when there
/// is one with `name` and `scene_category` columns (the mOSD benchmark's); empty otherwise.
std::map<std::string, std::string> CaseCategories(const std::string& cases_path);

/// Each case's model (its object's labelled points, in the camera frame of its capture) and
/// scene (the other capture, with the centroid of the object's labelled points as the truth).
/// With `only` non-empty, just the cases it names (each must exist); of those, every
/// `every`-th. False with `error` naming the file and case.
/// With `other_captures`, each case's model is instead every other capture of its object in the
/// file (daemon/eval/other_captures.h), its truth pose chained through the file's, aligned with
/// `parallel`; `log` gets each object's alignment.
struct CaseModels {
  bool other_captures = false;
  ParallelFor parallel = SerialFor;
  std::ostream* log = nullptr;
};
bool LoadCaseScenes(const std::string& path, const std::string& data_dir,
                    const std::vector<std::string>& only, int every, std::vector<EvalModel>* models,
                    std::vector<Scene>* scenes, std::string* error,
                    const CaseModels& case_models = {});

}  // namespace saccade::eval
