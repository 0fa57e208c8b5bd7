// `saccade eval`'s values (scenes, trials, attention runs) and its report on cross-capture
// cases: recall with its interval on the feasible cases, false instances per case, time, pose
// errors against the truth pose, per object and per category, where each miss was lost, and a
// cross-validation of the choice of configuration across objects.
#pragma once

#include "core/evaluation.h"
#include "core/recognition.h"
#include "io/config.h"
#include "io/frame_source.h"

#include <filesystem>
#include <iosfwd>
#include <optional>
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
};

/// What one configuration found in one frame with the fovea at one place.
struct Trial {
  double ms = 0;
  std::vector<Eigen::Vector3f> centres;  // each instance's model centre in the scene
  std::vector<Detection> instances;      // as reported, best first (correspondences dropped)
  RecognitionStats stats;
  CaseEvidence evidence;  // what the truth says of this run's stages
};

/// The attention loop's run from one fovea: frames until a detection within 8 cm of the truth
/// (0: not before it gave up), and the false instances it saw on the way.
struct Acquisition {
  int frames = 0;
  int false_instances = 0;
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

/// Writes `report.md` and `cases.csv` into `dir` for `runs` (per configuration, its protocols)
/// and prints the headline rows to `out`.
void WriteCaseReport(const std::string& cases_file, const std::vector<EvalConfiguration>& configs,
                     const std::vector<EvalModel>& models, const std::vector<Scene>& scenes,
                     const std::vector<std::vector<ProtocolRun>>& runs,
                     const std::filesystem::path& dir, std::ostream& out);

}  // namespace saccade::eval
