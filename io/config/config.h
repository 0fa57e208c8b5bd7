// Strict YAML configuration: every key must be known, of the right type and in range; errors
// name the file, the key and the reason.
#pragma once

#include "core/foveation.h"
#include "core/recognition.h"
#include "core/schema.h"
#include "core/sim/rerender.h"
#include "core/sim/scenario.h"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace saccade {

/// The keys of one YAML mapping, each bound to the field it sets; a setter throws on a wrong
/// type. Built by the owner of the fields, applied by ApplyConfigFile.
struct ConfigKeys {
  using Setter = std::function<void(const YAML::Node&)>;
  std::map<std::string, Setter> setters;

  ConfigKeys& Add(const std::string& key, Setter setter);
  ConfigKeys& Add(const std::string& key, bool* field);
  ConfigKeys& Add(const std::string& key, int* field);
  ConfigKeys& Add(const std::string& key, unsigned* field);
  ConfigKeys& Add(const std::string& key, float* field);
  ConfigKeys& Add(const std::string& key, double* field);
  ConfigKeys& Add(const std::string& key, std::string* field);
  ConfigKeys& Add(const std::string& key, Eigen::Vector2f* field);           // [x, z]
  ConfigKeys& Add(const std::string& key, Eigen::Vector3f* field);           // [x, y, z]
  ConfigKeys& Add(const std::string& key, Eigen::Quaternionf* field);        // [w, x, y, z]
  ConfigKeys& Add(const std::string& key, std::vector<std::string>* field);  // a list, or one
  ConfigKeys& Add(const std::string& key, std::vector<int>* field);          // a list, or one
  /// One of `names`; `set` gets the index of the name.
  ConfigKeys& AddChoice(const std::string& key, const std::vector<std::string>& names,
                        std::function<void(int)> set);
};

/// Every key of a configuration file: the top level's and each section's.
struct ConfigSchema {
  ConfigKeys top;
  std::map<std::string, ConfigKeys> sections;
};

/// Builds a ConfigSchema from an options struct's Serialize (core/schema.h): Visit binds a
/// key, Choice an enum key by its names, Section a mapping (one level deep).
class SchemaArchive {
 public:
  explicit SchemaArchive(ConfigSchema* schema) : schema_(schema), keys_(&schema->top) {}

  template <typename T>
  void Visit(const char* name, T* field) {
    keys_->Add(name, field);
  }
  template <typename Enum>
  void Choice(const char* name, Enum* field, ChoiceNames<Enum> names) {
    std::vector<std::string> labels;
    std::vector<Enum> values;
    for (const auto& [label, value] : names) labels.push_back(label), values.push_back(value);
    keys_->AddChoice(name, labels, [field, values](int i) { *field = values[i]; });
  }
  template <typename Options>
  void Section(const char* name, Options* options) {
    SchemaArchive section(schema_);
    section.keys_ = &schema_->sections[name];
    options->Serialize(&section);
  }

 private:
  ConfigSchema* schema_;
  ConfigKeys* keys_;  // where Visit and Choice add
};

/// The whole schema of a struct whose Serialize may have sections.
template <typename Options>
ConfigSchema SchemaOf(Options* options) {
  ConfigSchema schema;
  SchemaArchive archive(&schema);
  options->Serialize(&archive);
  return schema;
}
/// The keys of one options struct, for a section of its own.
template <typename Options>
ConfigKeys KeysOf(Options* options) {
  return SchemaOf(options).top;
}

/// Applies the file strictly: top-level keys from schema.top, mappings from schema.sections.
/// False with `error` = "FILE: key 'a.b': reason" on an unknown key or a wrong type (a renamed
/// key names its new name), and "FILE: line N: reason" when it is not YAML. An empty file
/// changes nothing. `set`, when given, gets the keys the file set ("section.key").
bool ApplyConfigFile(const std::string& path, const ConfigSchema& schema, std::string* error,
                     std::vector<std::string>* set = nullptr);

/// Warns (one log line each) about the keys of `set` that `recognition` ignores in its mode
/// (the hand radii while radii_from_model is on), `prefix` being how `set` names its section
/// ("recognition." or "configurations[2].recognition.").
void WarnIgnoredKeys(const std::string& path, const std::string& prefix,
                     const RecognitionOptions& recognition, const std::vector<std::string>& set);

/// The recognition part of a configuration file:
///   recognition: { <RecognitionOptions fields> }
///   fovea:       { <FoveaOptions fields>; vectors as [x, y, z], orientation as [w, x, y, z] }
/// Keys absent from the file keep the values already in the structs.
struct RecognitionConfig {
  RecognitionOptions recognition;
  FoveaOptions fovea;
};

/// Applies the file over `config`. False with `error` = "FILE: key 'a.b': reason" on any
/// unknown key, wrong type, out-of-range value or unreadable file.
bool LoadRecognitionConfig(const std::string& path, RecognitionConfig* config, std::string* error);

/// One configuration of an evaluation: how to search (foveated with our stages, plain with our
/// stages, or plain with PCL's stock stages: the paper's gold standard) and the options.
struct EvalConfiguration {
  enum class Pipeline { kFoveated, kPlain, kStock, kOpencvPpf };
  std::string name;
  Pipeline pipeline = Pipeline::kFoveated;
  RecognitionConfig config;

  /// How the configuration file names a pipeline.
  static constexpr ChoiceNames<Pipeline> kPipelineNames = {{"foveated", Pipeline::kFoveated},
                                                           {"plain", Pipeline::kPlain},
                                                           {"stock", Pipeline::kStock},
                                                           {"opencv-ppf", Pipeline::kOpencvPpf}};
  const char* PipelineName() const { return ChoiceName(pipeline, kPipelineNames); }
};

/// An evaluation's configurations file:
///   defaults: {recognition: {...}, fovea: {...}}   # optional, applied to every entry
///   configurations:
///     - {name: "1", pipeline: foveated, recognition: {...}, fovea: {...}}
/// Each entry starts from `base` with the file's defaults applied, then applies its own
/// sections; strict as LoadRecognitionConfig, errors name the entry
/// ("configurations[3].fovea.finest_level").
/// `extra` names further sections an entry may hold (the caller's own options, such as the
/// attention loop's): for entry i, the keys to apply its section to.
using ExtraSections = std::map<std::string, std::function<ConfigKeys(std::size_t entry)>>;
bool LoadEvalConfigurations(const std::string& path, const RecognitionConfig& base,
                            std::vector<EvalConfiguration>* out, std::string* error,
                            const ExtraSections& extra = {});

/// One cross-capture case: an object cut by its label out of one labelled capture, searched in
/// another capture where the same object appears (mOSD labels: object k = labels 10k..10k+9).
struct LabelledCase {
  std::string name;
  std::string model_file;  // resolved against the data folder
  int model_object = 0;
  std::string scene_file;
  int scene_object = 0;
  /// Optional truth beyond the labelled centroid: the model-to-scene pose (model capture frame
  /// to scene capture frame, metres), and whether the two captures share enough surface for any
  /// pose to be verified (an infeasible case is reported apart, not counted against recall).
  std::optional<Eigen::Matrix4f> truth_pose;
  bool feasible = true;
  /// What the case is of, for per-object and per-category tables; empty when not given (the
  /// evaluation then takes the identity from the name, up to its first '-').
  std::string identity;
  std::string category;
};

/// A cases file:
///   cases:
///     - {name: tin-31-in-44, model: {file: pcl_data/mOSD/test31.pcd, object: 2},
///        scene: {file: pcl_data/mOSD/test44.pcd, object: 2},
///        truth_pose: [16 numbers, row-major 4x4], feasible: true,   # optional
///        identity: cookie_tin, category: cylindric objects}          # optional
/// Relative files are resolved against `data_dir`. Strict as the other loaders.
bool LoadLabelledCases(const std::string& path, const std::string& data_dir,
                       std::vector<LabelledCase>* out, std::string* error);

/// A synthetic scenario file: `preset: NAME` (required, the starting point), then any of
/// name, frames, rate_hz, seed, table_height_m, occluded_from, occluded_frames, and the
/// sections target_motion / camera_motion (Trajectory fields; kind: static | linear | circular
/// | leave-return), noise (KinectNoise fields) and clutter (a list that replaces the preset's:
/// {kind: box, half_size_m: [x, y, z], xz_m: [x, z], yaw_rad} or {kind: sphere, radius_m,
/// xz_m}). Strict as LoadRecognitionConfig.
bool LoadScenario(const std::string& path, Scenario* scenario, std::string* error);

/// A real-capture sequence file (core/sim/rerender.h, CaptureSequence's keys): capture, object,
/// frames, rate_hz, and the sections camera_motion / object_motion (Trajectory fields). Strict
/// as LoadRecognitionConfig.
bool LoadCaptureSequence(const std::string& path, CaptureSequence* sequence, std::string* error);

}  // namespace saccade
