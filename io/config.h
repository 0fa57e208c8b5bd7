// Strict YAML configuration: every key must be known, of the right type and in range; errors
// name the file, the key and the reason.
#pragma once

#include "core/foveation.h"
#include "core/recognition.h"
#include "core/scenario.h"

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
  ConfigKeys& Add(const std::string& key, Eigen::Vector3f* field);           // [x, y, z]
  ConfigKeys& Add(const std::string& key, Eigen::Quaternionf* field);        // [w, x, y, z]
  ConfigKeys& Add(const std::string& key, std::vector<std::string>* field);  // a list, or one
  /// One of `names`; the field gets the index of the name.
  ConfigKeys& AddChoice(const std::string& key, int* field, const std::vector<std::string>& names);
};

/// The keys of RecognitionOptions and FoveaOptions, as in configs/paper.yaml.
ConfigKeys RecognitionKeys(RecognitionOptions* options);
ConfigKeys FoveaKeys(FoveaOptions* options);

/// Applies the file strictly: top-level keys from `top`, mappings from `sections`. False with
/// `error` = "FILE: key 'a.b': reason" on an unknown key or a wrong type, and
/// "FILE: line N: reason" when it is not YAML. An empty file changes nothing.
bool ApplyConfigFile(const std::string& path, const ConfigKeys& top,
                     const std::map<std::string, ConfigKeys>& sections, std::string* error);

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
  std::string name;
  std::string pipeline = "foveated";  // foveated | plain | stock (PCL) | opencv-ppf (OpenCV)
  RecognitionConfig config;
};

/// An evaluation's configurations file:
///   defaults: {recognition: {...}, fovea: {...}}   # optional, applied to every entry
///   configurations:
///     - {name: "1", pipeline: foveated, recognition: {...}, fovea: {...}}
/// Each entry starts from `base` with the file's defaults applied, then applies its own
/// sections; strict as LoadRecognitionConfig, errors name the entry
/// ("configurations[3].fovea.levels_m").
bool LoadEvalConfigurations(const std::string& path, const RecognitionConfig& base,
                            std::vector<EvalConfiguration>* out, std::string* error);

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

}  // namespace saccade
