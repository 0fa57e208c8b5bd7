#include "daemon/settings.h"

#include <cmath>

#include "core/fail.h"
#include "io/base/log.h"
#include "io/config/config.h"

namespace saccade {

DaemonSettings PaperDefaults() {
  DaemonSettings s;
  s.recognition = RecognitionOptions::Paper();  // Table 1
  s.fovea.finest_level = 3;                     // Table 2
  s.fovea.outer_box_from_scene = false;         // its fixed S_0 and Delta
  s.fovea.inner_size_m = Eigen::Vector3f::Constant(0.5f);
  s.fovea.outer_keypoint_radius_m = 0.08f;
  s.fovea.inner_keypoint_radius_m = 0.02f;
  s.attention.search = SearchKind::kGrow;  // §3.4: G grows from the last fixation
  s.attention.acquire_confidence = 0;      // and the first instance found is followed
  s.attention.land_on_candidate_m = 0;     // where it was aimed
  return s;
}

bool PipelineOptions::IsValid(std::string* error) const {
  if (frames_in_flight < 1 || frames_in_flight > 16)
    return Fail(error, "frames_in_flight must be in [1, 16]");
  if (threads < 0) return Fail(error, "threads must be >= 0");
  return true;
}

bool ServiceOptions::IsValid(std::string* error) const {
  // (An endless period once made the status thread's sleep outlast SIGTERM.)
  if (!(status_period_s >= 0.05 && status_period_s <= 3600))
    return Fail(error, "status_period_s must be from 0.05 to 3600 seconds");
  return true;
}

bool SourceOptions::IsValid(std::string* error) const {
  if (spec.empty()) return Fail(error, "spec must name a frame source");
  if (!(wait_at_start_s >= 0) || !std::isfinite(wait_at_start_s))
    return Fail(error, "wait_at_start_s must be a finite number of seconds >= 0");
  return true;
}

bool DaemonSettings::IsValid(std::string* error) const {
  std::string why;
  if (!initial_fovea_m.allFinite()) return Fail(error, "initial_fovea_m must be finite");
  const auto check = [&](const char* section, auto& options) {
    if (options.IsValid(&why)) return true;
    return Fail(error, std::string(section) + ": " + why);
  };
  return check("source", source) && check("recognition", recognition) && check("fovea", fovea) &&
         check("attention", attention) && check("candidates", candidates) &&
         check("tracking", tracking) && check("saliency", saliency) &&
         check("pipeline", pipeline) && check("lcm", bus) && check("robot_frame", bus.robot) &&
         check("service", service) && check("preview", preview) && check("ros2", ros2) &&
         check("log", log);
}

bool LoadDaemonSettings(const std::string& path, DaemonSettings* settings, std::string* error) {
  DaemonSettings s = *settings;
  ConfigSchema schema = SchemaOf(&s);
  // G is the attention loop's to set, every frame.
  schema.sections["fovea"].setters.erase("growth_m");
  // `source: SPEC` is the section's spec alone.
  schema.top.Add("source", &s.source.spec);
  std::vector<std::string> set;
  if (!ApplyConfigFile(path, schema, error, &set)) {
    if (error->find("key 'fovea.growth_m': unknown key") != std::string::npos)
      Fail(error, path +
                      ": key 'fovea.growth_m': set by the attention loop in saccaded (see the "
                      "attention section's growth_* keys)");
    return false;
  }
  WarnIgnoredKeys(path, "recognition.", s.recognition, set);
  std::string why;
  if (!s.IsValid(&why)) {
    return Fail(error, path + ": " + why);
  }
  *settings = s;
  return true;
}

}  // namespace saccade
