#include "io/config/config.h"

#include "core/fail.h"
#include "io/base/log.h"
#include "io/base/text.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <functional>
#include <map>

namespace saccade {
namespace {

// Reads one value; throws YAML::Exception (caught below) on a type mismatch.
using Setter = std::function<void(const YAML::Node&)>;

// A number of type T (float or double); .nan and .inf are numbers to YAML but no setting's value.
template <typename T>
T FiniteNumber(const YAML::Node& n) {
  const T v = n.as<T>();
  if (!std::isfinite(v)) throw YAML::Exception(n.Mark(), "expected a finite number");
  return v;
}

template <typename T>
Setter Scalar(T* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "expected a scalar");
    if constexpr (std::is_floating_point_v<T>)
      *field = FiniteNumber<T>(n);
    else
      *field = n.as<T>();
  };
}

Setter Vector3(Eigen::Vector3f* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 3)
      throw YAML::Exception(n.Mark(), "expected a list of 3 numbers [x, y, z]");
    for (int i = 0; i < 3; ++i) (*field)[i] = FiniteNumber<float>(n[i]);
  };
}

Setter Quaternion(Eigen::Quaternionf* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 4)
      throw YAML::Exception(n.Mark(), "expected a list of 4 numbers [w, x, y, z]");
    const Eigen::Quaternionf q(FiniteNumber<float>(n[0]), FiniteNumber<float>(n[1]),
                               FiniteNumber<float>(n[2]), FiniteNumber<float>(n[3]));
    if (!(q.norm() > 1e-6f))
      throw YAML::Exception(n.Mark(), "expected a rotation: [0, 0, 0, 0] turns nothing");
    *field = q;
  };
}

Setter Matrix4(std::optional<Eigen::Matrix4f>* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 16)
      throw YAML::Exception(n.Mark(), "expected a list of 16 numbers (a 4x4 matrix, row-major)");
    Eigen::Matrix4f m;
    for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = n[i].as<float>();
    if (!m.allFinite() || !m.row(3).isApprox(Eigen::RowVector4f(0, 0, 0, 1)))
      throw YAML::Exception(n.Mark(), "expected a rigid transform with last row 0 0 0 1");
    *field = m;
  };
}

Setter Vector2(Eigen::Vector2f* field) {
  return [field](const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 2)
      throw YAML::Exception(n.Mark(), "expected a list of 2 numbers [x, z]");
    for (int i = 0; i < 2; ++i) (*field)[i] = FiniteNumber<float>(n[i]);
  };
}

// A mapping key as text. A key that is itself a list or a mapping ({a: 1}: 2 is valid YAML)
// names nothing here: refused, where yaml-cpp's as<std::string>() would throw.
bool KeyText(const YAML::Node& key, const std::string& where, const std::string& path,
             std::string* text, std::string* error) {
  if (key.IsNull()) {  // `~: 1`: no name, an unknown key as before
    *text = "null";
    return true;
  }
  if (!key.IsScalar()) {
    return Fail(error, path + ": line " + std::to_string(key.Mark().line + 1) + ": a key" +
                           (where.empty() ? "" : " in '" + where + "'") +
                           " is a list or a mapping, not a name");
  }
  *text = key.Scalar();
  return true;
}

// A key given twice in one mapping, anywhere in the document, is refused (YAML forbids it;
// yaml-cpp keeps both, and the last would silently win): false naming both lines.
bool NoKeyTwice(const YAML::Node& node, const std::string& path, std::string* error,
                int depth = 0) {
  if (depth > 64) return Fail(error, path + ": nested more than 64 levels deep, not a config");
  if (node.IsSequence()) {
    for (const auto& item : node)
      if (!NoKeyTwice(item, path, error, depth + 1)) return false;
  } else if (node.IsMap()) {
    std::map<std::string, int> seen;  // a scalar key -> its line
    for (const auto& kv : node) {
      if (kv.first.IsScalar()) {
        const int line = kv.first.Mark().line + 1;
        const auto [at, first] = seen.emplace(kv.first.Scalar(), line);
        if (!first)
          return Fail(error, path + ": line " + std::to_string(line) + ": key '" +
                                 kv.first.Scalar() + "' is given twice (first on line " +
                                 std::to_string(at->second) + ")");
      }
      if (!NoKeyTwice(kv.second, path, error, depth + 1)) return false;
    }
  }
  return true;
}

// Sets `key` from `value` with its setter; `qualified` names it in errors ("section.key").
bool ApplyKey(const std::map<std::string, Setter>& setters, const std::string& key,
              const std::string& qualified, const YAML::Node& value, const std::string& path,
              std::string* error) {
  auto it = setters.find(key);
  if (it == setters.end()) {
    // Keys renamed for readability (issue 20): say what they are called now.
    static const std::map<std::string, std::string> kRenamed = {
        {"levels_m", "finest_level"},
        {"density_0_m", "outer_density_m"},
        {"density_m_m", "inner_density_m"},
        {"keypoint_radius_0_m", "outer_keypoint_radius_m"},
        {"keypoint_radius_m_m", "inner_keypoint_radius_m"}};
    const auto renamed = kRenamed.find(key);
    return Fail(error,
                path + ": key '" + qualified + "': unknown key" +
                    (renamed == kRenamed.end() ? "" : " (it is now '" + renamed->second + "')"));
  }
  try {
    it->second(value);
  } catch (const YAML::Exception& e) {
    return Fail(error, path + ": key '" + qualified + "': wrong type (" + e.msg + ")");
  }
  return true;
}

bool ApplySection(const YAML::Node& section, const std::string& name,
                  const std::map<std::string, Setter>& setters, const std::string& path,
                  std::string* error, std::vector<std::string>* set = nullptr) {
  if (!section.IsMap()) {
    return Fail(error, path + ": key '" + name + "': expected a mapping");
  }
  for (const auto& kv : section) {
    std::string key;
    if (!KeyText(kv.first, name, path, &key, error)) return false;
    if (!ApplyKey(setters, key, name + "." + key, kv.second, path, error)) return false;
    if (set) set->push_back(name + "." + key);
  }
  return true;
}

// A mapping's keys applied through `schema`: its top keys and its sections, named in errors
// and in `set` after `prefix` ("" or "configurations[2].").
bool ApplySchema(const YAML::Node& node, const ConfigSchema& schema, const std::string& prefix,
                 const std::string& path, std::string* error, std::vector<std::string>* set) {
  for (const auto& kv : node) {
    std::string key;
    if (!KeyText(kv.first, prefix.empty() ? "" : prefix.substr(0, prefix.size() - 1), path, &key,
                 error))
      return false;
    // A key that is both a section and a plain key (source: SPEC, or source: {spec: ...}) is
    // the section when it is a mapping.
    const auto section = schema.sections.find(key);
    if (section != schema.sections.end() &&
        (kv.second.IsMap() || schema.top.setters.count(key) == 0)) {
      if (!ApplySection(kv.second, prefix + key, section->second.setters, path, error, set))
        return false;
    } else if (!ApplyKey(schema.top.setters, key, prefix + key, kv.second, path, error)) {
      return false;
    } else if (set) {
      set->push_back(prefix + key);
    }
  }
  return true;
}

// Parses the file; a null node for an empty file. False with `error` when unreadable or when
// the top level is not a mapping.
bool LoadRoot(const std::string& path, YAML::Node* root, std::string* error) {
  // Regular files only, of a config's size: a folder made yaml-cpp's stream throw past its own
  // exceptions, and a FIFO or a device would block or never end.
  std::uint64_t size = 0;
  if (!StatRegularFile(path, "a YAML file", &size, error)) return false;
  if (size > (16 << 20)) return Fail(error, path + ": larger than 16 MB, not a config");
  try {
    *root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    return Fail(error, path + ": cannot open file");
  } catch (const YAML::Exception& e) {
    return Fail(error, path + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  } catch (const std::exception& e) {
    return Fail(error, path + ": cannot read (" + std::string(e.what()) + ")");
  }
  if (!root->IsNull() && !root->IsMap()) {
    return Fail(error, path + ": top level must be a mapping");
  }
  return NoKeyTwice(*root, path, error);
}

// clutter: a list replacing the preset's, each item
//   {kind: box, half_size_m: [x, y, z], xz_m: [x, z], yaw_rad: a}  or
//   {kind: sphere, radius_m: r, xz_m: [x, z]}
bool LoadClutter(const YAML::Node& list, const std::string& path,
                 std::vector<Scenario::Clutter>* clutter, std::string* error) {
  if (!list.IsSequence()) {
    return Fail(error, path + ": key 'clutter': expected a list of objects");
  }
  clutter->clear();
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string name = "clutter[" + std::to_string(i) + "]";
    std::string kind;
    Eigen::Vector3f half = Eigen::Vector3f::Constant(0.05f);
    float radius = 0.05f;
    Scenario::Clutter c;
    const std::map<std::string, Setter> keys = {
        {"kind", Scalar(&kind)},    {"half_size_m", Vector3(&half)}, {"radius_m", Scalar(&radius)},
        {"xz_m", Vector2(&c.xz_m)}, {"yaw_rad", Scalar(&c.yaw_rad)},
    };
    if (!ApplySection(list[i], name, keys, path, error)) return false;
    if (kind == "box" && (half.array() > 0).all()) {
      c.shape.parts.push_back(Shape::Part::Box(Eigen::Vector3f::Zero(), half));
      c.bottom_y_m = half.y();
    } else if (kind == "sphere" && radius > 0) {
      c.shape.parts.push_back(Shape::Part::Sphere(Eigen::Vector3f::Zero(), radius));
      c.bottom_y_m = radius;
    } else {
      return Fail(error, path + ": key '" + name +
                             "': kind must be box (half_size_m > 0) or sphere " + "(radius_m > 0)");
    }
    clutter->push_back(c);
  }
  return true;
}

}  // namespace

bool LoadScenario(const std::string& path, Scenario* scenario, std::string* error) {
  YAML::Node root;
  if (!LoadRoot(path, &root, error)) return false;
  if (root.IsNull() || !root["preset"]) {
    return Fail(error,
                path + ": key 'preset': required (one of the named scenarios to start from)");
  }
  if (!root["preset"].IsScalar())  // a list or a mapping: yaml-cpp's as<std::string> throws
    return Fail(error, path + ": key 'preset': expected a scenario's name");
  const auto preset = ScenarioPreset(root["preset"].Scalar());
  if (!preset) {
    return Fail(error, path + ": key 'preset': unknown scenario '" + root["preset"].Scalar() + "'");
  }
  Scenario& s = *scenario;
  s = *preset;
  const std::map<std::string, Setter> top = {
      {"preset", [](const YAML::Node&) {}},
      {"name", Scalar(&s.name)},
      {"frames", Scalar(&s.frames)},
      {"rate_hz", Scalar(&s.rate_hz)},
      {"seed", Scalar(&s.seed)},
      {"table_height_m", Scalar(&s.table_height_m)},
      {"occluded_from", Scalar(&s.occluded_from)},
      {"occluded_frames", Scalar(&s.occluded_frames)},
  };
  const std::map<std::string, std::map<std::string, Setter>> sections = {
      {"target_motion", KeysOf(&s.target_motion).setters},
      {"camera_motion", KeysOf(&s.camera_motion).setters},
      {"noise", KeysOf(&s.noise).setters},
  };
  for (const auto& kv : root) {
    std::string key;
    if (!KeyText(kv.first, "", path, &key, error)) return false;
    if (key == "clutter") {
      if (!LoadClutter(kv.second, path, &s.clutter, error)) return false;
      continue;
    }
    if (auto section = sections.find(key); section != sections.end()) {
      if (!ApplySection(kv.second, key, section->second, path, error)) return false;
      continue;
    }
    if (!ApplyKey(top, key, key, kv.second, path, error)) return false;
  }
  std::string why;
  if (!s.IsValid(&why)) {
    return Fail(error, path + ": " + why);
  }
  return true;
}

bool LoadCaptureSequence(const std::string& path, CaptureSequence* sequence, std::string* error) {
  CaptureSequence s = *sequence;
  if (!ApplyConfigFile(path, SchemaOf(&s), error)) return false;
  std::string why;
  if (!s.IsValid(&why)) return Fail(error, path + ": " + why);
  *sequence = s;
  return true;
}

namespace {

// A list of `what`s, or one alone.
template <typename T>
Setter ListOf(std::vector<T>* f, const std::string& what) {
  return [f, what](const YAML::Node& n) {
    if (n.IsScalar()) {
      *f = {n.as<T>()};
      return;
    }
    if (!n.IsSequence()) throw YAML::Exception(n.Mark(), "expected " + what + " or a list");
    f->clear();
    for (const auto& item : n) {
      if (!item.IsScalar()) throw YAML::Exception(item.Mark(), "expected " + what);
      f->push_back(item.as<T>());
    }
  };
}

}  // namespace

ConfigKeys& ConfigKeys::Add(const std::string& key, Setter setter) {
  setters[key] = std::move(setter);
  return *this;
}
ConfigKeys& ConfigKeys::Add(const std::string& key, bool* f) { return Add(key, Scalar(f)); }
ConfigKeys& ConfigKeys::Add(const std::string& key, int* f) { return Add(key, Scalar(f)); }
ConfigKeys& ConfigKeys::Add(const std::string& key, unsigned* f) { return Add(key, Scalar(f)); }
ConfigKeys& ConfigKeys::Add(const std::string& key, float* f) { return Add(key, Scalar(f)); }
ConfigKeys& ConfigKeys::Add(const std::string& key, double* f) { return Add(key, Scalar(f)); }
ConfigKeys& ConfigKeys::Add(const std::string& key, std::string* f) { return Add(key, Scalar(f)); }
ConfigKeys& ConfigKeys::Add(const std::string& key, Eigen::Vector2f* f) {
  return Add(key, Vector2(f));
}
ConfigKeys& ConfigKeys::Add(const std::string& key, Eigen::Vector3f* f) {
  return Add(key, Vector3(f));
}
ConfigKeys& ConfigKeys::Add(const std::string& key, Eigen::Quaternionf* f) {
  return Add(key, Quaternion(f));
}
ConfigKeys& ConfigKeys::Add(const std::string& key, std::vector<std::string>* f) {
  return Add(key, ListOf(f, "a string"));
}
ConfigKeys& ConfigKeys::Add(const std::string& key, std::vector<int>* f) {
  return Add(key, ListOf(f, "a number"));
}
ConfigKeys& ConfigKeys::AddChoice(const std::string& key, const std::vector<std::string>& names,
                                  std::function<void(int)> set) {
  return Add(key, [set, names](const YAML::Node& n) {
    const std::string value = n.IsScalar() ? n.as<std::string>() : "";
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i] == value) {
        set(static_cast<int>(i));
        return;
      }
    }
    std::string expected;
    for (const auto& name : names) expected += (expected.empty() ? "" : " | ") + name;
    throw YAML::Exception(n.Mark(), "expected " + expected);
  });
}

bool ApplyConfigFile(const std::string& path, const ConfigSchema& schema, std::string* error,
                     std::vector<std::string>* set) {
  YAML::Node root;
  if (!LoadRoot(path, &root, error)) return false;
  if (root.IsNull()) return true;
  return ApplySchema(root, schema, "", path, error, set);
}

void WarnIgnoredKeys(const std::string& path, const std::string& prefix,
                     const RecognitionOptions& recognition, const std::vector<std::string>& set) {
  for (const std::string& key : recognition.IgnoredKeys())
    if (std::find(set.begin(), set.end(), prefix + key) != set.end())
      Log(LogLevel::kWarning, path + ": key '" + prefix + key +
                                  "' is ignored while radii_from_model is true (the radii are "
                                  "fitted to each model)");
}

bool LoadRecognitionConfig(const std::string& path, RecognitionConfig* config, std::string* error) {
  RecognitionOptions& r = config->recognition;
  FoveaOptions& f = config->fovea;
  ConfigSchema schema;
  schema.sections = {{"recognition", KeysOf(&r)}, {"fovea", KeysOf(&f)}};
  std::vector<std::string> set;
  if (!ApplyConfigFile(path, schema, error, &set)) return false;
  WarnIgnoredKeys(path, "recognition.", r, set);
  std::string why;
  if (!r.IsValid(&why)) {
    return Fail(error, path + ": recognition: " + why);
  }
  if (!f.IsValid(&why)) {
    return Fail(error, path + ": fovea: " + why);
  }
  return true;
}

namespace {

// A file holding the key `list_key`, whose value is a list of mappings, and optionally
// `header_key` (handed to `header` first): calls `entry` with each mapping, its index and its
// name for errors ("list[3]"), stopping at the first false.
using EntryFn = std::function<bool(const YAML::Node&, std::size_t, const std::string&)>;
bool ForEachListEntry(const std::string& path, const std::string& list_key, const EntryFn& entry,
                      std::string* error, const std::string& header_key = "",
                      const std::function<bool(const YAML::Node&)>& header = nullptr) {
  YAML::Node root;
  if (!LoadRoot(path, &root, error)) return false;
  const bool has_header = !header_key.empty() && root.IsMap() && root[header_key];
  if (root.IsNull() || !root[list_key] || !root[list_key].IsSequence() ||
      root.size() != 1 + (has_header ? 1 : 0)) {
    return Fail(error, path + ": expected the key '" + list_key + "', holding a list" +
                           (header_key.empty() ? std::string(", and nothing else")
                                               : ", and at most '" + header_key + "' beside it"));
  }
  if (has_header && !header(root[header_key])) return false;
  const YAML::Node list = root[list_key];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string name = list_key + "[" + std::to_string(i) + "]";
    if (!list[i].IsMap()) {
      return Fail(error, path + ": key '" + name + "': expected a mapping");
    }
    if (!entry(list[i], i, name)) return false;
  }
  return true;
}

// The `recognition` and `fovea` sections of `node` (named `name` in errors) applied to `config`.
bool ApplyRecognitionAndFovea(const YAML::Node& node, const std::string& name,
                              RecognitionConfig* config, const std::string& path,
                              std::string* error, std::vector<std::string>* set = nullptr) {
  const ConfigKeys recognition = KeysOf(&config->recognition);
  const ConfigKeys fovea = KeysOf(&config->fovea);
  const std::map<std::string, const std::map<std::string, Setter>*> sections = {
      {"recognition", &recognition.setters}, {"fovea", &fovea.setters}};
  for (const auto& kv : node) {
    std::string key;
    if (!KeyText(kv.first, name, path, &key, error)) return false;
    const auto section = sections.find(key);
    if (section == sections.end()) {
      return Fail(error,
                  path + ": key '" + name + "." + key + "': unknown (expected recognition, fovea)");
    }
    if (!ApplySection(kv.second, name + "." + key, *section->second, path, error, set))
      return false;
  }
  return true;
}

}  // namespace

bool LoadEvalConfigurations(const std::string& path, const RecognitionConfig& base,
                            std::vector<EvalConfiguration>* out, std::string* error,
                            const ExtraSections& extra) {
  out->clear();
  RecognitionConfig defaults = base;
  const auto apply_defaults = [&](const YAML::Node& node) {
    if (!node.IsMap()) {
      return Fail(error, path + ": key 'defaults': expected a mapping");
    }
    return ApplyRecognitionAndFovea(node, "defaults", &defaults, path, error);
  };
  return ForEachListEntry(
      path, "configurations",
      [&](const YAML::Node& node, std::size_t i, const std::string& entry) {
        EvalConfiguration c;
        c.config = defaults;
        c.name = std::to_string(i);
        ConfigKeys top;
        top.Add("name", &c.name);
        std::vector<std::string> pipelines;
        for (const auto& [label, value] : EvalConfiguration::kPipelineNames)
          pipelines.push_back(label);
        top.AddChoice("pipeline", pipelines, [&c](int k) {
          c.pipeline = std::data(EvalConfiguration::kPipelineNames)[k].second;
        });
        YAML::Node sections;
        for (const auto& kv : node) {
          std::string key;
          if (!KeyText(kv.first, entry, path, &key, error)) return false;
          if (key == "recognition" || key == "fovea") {
            sections[key] = kv.second;
          } else if (const auto it = extra.find(key); it != extra.end()) {
            if (!ApplySection(kv.second, entry + "." + key, it->second(i).setters, path, error))
              return false;
          } else if (!ApplyKey(top.setters, key, entry + "." + key, kv.second, path, error)) {
            return false;
          }
        }
        std::vector<std::string> set;
        if (!ApplyRecognitionAndFovea(sections, entry, &c.config, path, error, &set)) return false;
        WarnIgnoredKeys(path, entry + ".recognition.", c.config.recognition, set);
        std::string why;
        if (!c.config.recognition.IsValid(&why) || !c.config.fovea.IsValid(&why)) {
          return Fail(error, path + ": " + entry + " (" + c.name + "): " + why);
        }
        out->push_back(std::move(c));
        return true;
      },
      error, "defaults", apply_defaults);
}

bool LoadLabelledCases(const std::string& path, const std::string& data_dir,
                       std::vector<LabelledCase>* out, std::string* error) {
  out->clear();
  return ForEachListEntry(
      path, "cases",
      [&](const YAML::Node& node, std::size_t i, const std::string& entry) {
        LabelledCase c;
        const std::map<std::string, Setter> capture_model = {{"file", Scalar(&c.model_file)},
                                                             {"object", Scalar(&c.model_object)}};
        const std::map<std::string, Setter> capture_scene = {{"file", Scalar(&c.scene_file)},
                                                             {"object", Scalar(&c.scene_object)}};
        const std::map<std::string, Setter> top = {{"name", Scalar(&c.name)},
                                                   {"truth_pose", Matrix4(&c.truth_pose)},
                                                   {"feasible", Scalar(&c.feasible)},
                                                   {"identity", Scalar(&c.identity)},
                                                   {"category", Scalar(&c.category)}};
        for (const auto& kv : node) {
          std::string key;
          if (!KeyText(kv.first, entry, path, &key, error)) return false;
          const std::string qualified = entry + "." + key;
          const bool ok =
              key == "model"   ? ApplySection(kv.second, qualified, capture_model, path, error)
              : key == "scene" ? ApplySection(kv.second, qualified, capture_scene, path, error)
                               : ApplyKey(top, key, qualified, kv.second, path, error);
          if (!ok) return false;
        }
        const auto check = [&](const char* what, std::string* file, int object) {
          if (file->empty() || object < 1) {
            return Fail(error, path + ": key '" + entry + "." + what +
                                   "': needs a file and an object >= 1");
          }
          if ((*file)[0] != '/') *file = data_dir + "/" + *file;
          return true;
        };
        if (!check("model", &c.model_file, c.model_object) ||
            !check("scene", &c.scene_file, c.scene_object))
          return false;
        if (c.name.empty()) c.name = std::to_string(i);
        out->push_back(std::move(c));
        return true;
      },
      error);
}

}  // namespace saccade
