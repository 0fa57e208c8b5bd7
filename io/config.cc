#include "io/config.h"

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>

namespace saccade {
namespace {

// Reads one value; throws YAML::Exception (caught below) on a type mismatch.
using Setter = std::function<void(const YAML::Node&)>;

template <typename T>
Setter Scalar(T* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "expected a scalar");
    *field = n.as<T>();
  };
}

Setter Vector3(Eigen::Vector3f* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 3)
      throw YAML::Exception(n.Mark(), "expected a list of 3 numbers [x, y, z]");
    for (int i = 0; i < 3; ++i) (*field)[i] = n[i].as<float>();
  };
}

Setter Quaternion(Eigen::Quaternionf* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 4)
      throw YAML::Exception(n.Mark(), "expected a list of 4 numbers [w, x, y, z]");
    *field =
        Eigen::Quaternionf(n[0].as<float>(), n[1].as<float>(), n[2].as<float>(), n[3].as<float>());
  };
}

bool ApplySection(const YAML::Node& section, const std::string& name,
                  const std::map<std::string, Setter>& setters, const std::string& path,
                  std::string* error) {
  if (!section.IsMap()) {
    *error = path + ": key '" + name + "': expected a mapping";
    return false;
  }
  for (const auto& kv : section) {
    const std::string key = kv.first.as<std::string>();
    auto it = setters.find(key);
    if (it == setters.end()) {
      *error = path + ": key '" + name + "." + key + "': unknown key";
      return false;
    }
    try {
      it->second(kv.second);
    } catch (const YAML::Exception& e) {
      *error = path + ": key '" + name + "." + key + "': wrong type (" + e.msg + ")";
      return false;
    }
  }
  return true;
}

}  // namespace

bool LoadRecognitionConfig(const std::string& path, RecognitionConfig* config, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    *error = path + ": cannot open config file";
    return false;
  } catch (const YAML::Exception& e) {
    *error = path + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg;
    return false;
  }
  if (root.IsNull()) return true;  // an empty file changes nothing
  if (!root.IsMap()) {
    *error = path + ": top level must be a mapping";
    return false;
  }
  RecognitionOptions& r = config->recognition;
  FoveaOptions& f = config->fovea;
  const std::map<std::string, Setter> recognition = {
      {"scene_normal_neighbors", Scalar(&r.scene_normal_neighbors)},
      {"scene_keypoint_radius_m", Scalar(&r.scene_keypoint_radius_m)},
      {"scene_shot_radius_m", Scalar(&r.scene_shot_radius_m)},
      {"scene_lrf_radius_m", Scalar(&r.scene_lrf_radius_m)},
      {"model_normal_neighbors", Scalar(&r.model_normal_neighbors)},
      {"model_keypoint_radius_m", Scalar(&r.model_keypoint_radius_m)},
      {"model_shot_radius_m", Scalar(&r.model_shot_radius_m)},
      {"model_lrf_radius_m", Scalar(&r.model_lrf_radius_m)},
      {"max_descriptor_sqr_distance", Scalar(&r.max_descriptor_sqr_distance)},
      {"hough_bin_m", Scalar(&r.hough_bin_m)},
      {"hough_threshold", Scalar(&r.hough_threshold)},
      {"pose_inlier_threshold_m", Scalar(&r.pose_inlier_threshold_m)},
      {"max_described_density_m", Scalar(&r.max_described_density_m)},
      {"match_branching", Scalar(&r.match_branching)},
      {"match_checks", Scalar(&r.match_checks)},
      {"match_seed", Scalar(&r.match_seed)},
  };
  const std::map<std::string, Setter> fovea = {
      {"levels_m", Scalar(&f.levels_m)},
      {"outer_box_from_scene", Scalar(&f.outer_box_from_scene)},
      {"outer_size_m", Vector3(&f.outer_size_m)},
      {"outer_min_corner_m", Vector3(&f.outer_min_corner_m)},
      {"outer_orientation", Quaternion(&f.outer_orientation)},
      {"inner_size_m", Vector3(&f.inner_size_m)},
      {"growth_m", Vector3(&f.growth_m)},
      {"density_0_m", Scalar(&f.density_0_m)},
      {"density_m_m", Scalar(&f.density_m_m)},
      {"keypoint_radius_0_m", Scalar(&f.keypoint_radius_0_m)},
      {"keypoint_radius_m_m", Scalar(&f.keypoint_radius_m_m)},
  };
  for (const auto& kv : root) {
    const std::string section = kv.first.as<std::string>();
    bool ok;
    if (section == "recognition")
      ok = ApplySection(kv.second, section, recognition, path, error);
    else if (section == "fovea")
      ok = ApplySection(kv.second, section, fovea, path, error);
    else {
      *error = path + ": key '" + section + "': unknown key";
      ok = false;
    }
    if (!ok) return false;
  }
  std::string why;
  if (!r.IsValid(&why)) {
    *error = path + ": recognition: " + why;
    return false;
  }
  if (!f.IsValid(&why)) {
    *error = path + ": fovea: " + why;
    return false;
  }
  return true;
}

}  // namespace saccade
