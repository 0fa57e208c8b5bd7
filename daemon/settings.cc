#include "daemon/settings.h"

#include "core/fail.h"
#include "io/config.h"
#include "io/log.h"

namespace saccade {

DaemonSettings PaperDefaults() {
  DaemonSettings s;
  s.recognition = RecognitionOptions::Paper();  // Table 1
  s.fovea.levels_m = 3;                         // Table 2
  s.fovea.inner_size_m = Eigen::Vector3f::Constant(0.5f);
  s.fovea.keypoint_radius_0_m = 0.08f;
  s.fovea.keypoint_radius_m_m = 0.02f;
  return s;
}

bool DaemonSettings::IsValid(std::string* error) const {
  std::string why;
  if (!recognition.IsValid(&why)) return Fail(error, "recognition: " + why);
  if (!fovea.IsValid(&why)) return Fail(error, "fovea: " + why);
  if (!attention.IsValid(&why)) return Fail(error, "attention: " + why);
  if (!initial_fovea_m.allFinite()) return Fail(error, "key 'initial_fovea_m': must be finite");
  if (saliency.stride_px < 1) return Fail(error, "key 'saliency.stride_px': must be >= 1");
  if (!(saliency.cell_m > 0)) return Fail(error, "key 'saliency.cell_m': must be > 0");
  if (!(saliency.edge_jump_m > 0)) return Fail(error, "key 'saliency.edge_jump_m': must be > 0");
  if (saliency.max_regions < 1) return Fail(error, "key 'saliency.max_regions': must be >= 1");
  if (frames_in_flight < 1 || frames_in_flight > 16)
    return Fail(error, "key 'pipeline.frames_in_flight': must be in [1, 16]");
  if (threads < 0) return Fail(error, "key 'pipeline.threads': must be >= 0");
  if (bus.url.empty()) return Fail(error, "key 'lcm.url': must not be empty");
  if (bus.channel_prefix.empty()) return Fail(error, "key 'lcm.channel_prefix': must not be empty");
  if (!(bus.max_fovea_distance_m > 0))
    return Fail(error, "key 'lcm.max_fovea_distance_m': must be > 0");
  if (!bus.robot_from_camera.matrix().allFinite())
    return Fail(error, "key 'robot_frame': the transform must be finite");
  LogLevel level;
  if (!ParseLogLevel(log_level, &level))
    return Fail(error, "key 'service.log_level': expected debug | info | warning | error");
  if (!(status_period_s >= 0.05))
    return Fail(error, "key 'service.status_period_s': must be >= 0.05");
  if (summary != "off" && summary != "line")
    return Fail(error, "key 'service.summary': expected off | line");
  return true;
}

bool LoadDaemonSettings(const std::string& path, DaemonSettings* settings, std::string* error) {
  DaemonSettings s = *settings;
  AttentionOptions& a = s.attention;
  int growth_kind = static_cast<int>(a.growth_kind);
  int fallback = static_cast<int>(a.fallback);
  Eigen::Vector3f robot_translation = s.bus.robot_from_camera.translation();
  Eigen::Quaternionf robot_rotation(s.bus.robot_from_camera.rotation());

  ConfigKeys top;
  top.Add("source", &s.source).Add("model", &s.models).Add("initial_fovea_m", &s.initial_fovea_m);
  ConfigKeys attention;
  attention.Add("growth_min_m", &a.growth_min_m)
      .Add("growth_max_m", &a.growth_max_m)
      .AddChoice("growth", &growth_kind, {"additive", "multiplicative"})
      .Add("growth_step", &a.growth_step)
      .Add("growth_floor_m", &a.growth_floor_m)
      .AddChoice("fallback", &fallback, {"full_scan", "saccade"})
      .Add("saccade_region_m", &a.saccade_region_m)
      .Add("max_targets", &a.max_targets)
      .Add("same_target_m", &a.same_target_m)
      .Add("predict", &a.predict)
      .Add("predict_max_horizon_s", &a.predict_max_horizon_s)
      .Add("velocity_smoothing", &a.velocity_smoothing);
  ConfigKeys saliency;
  saliency.Add("stride_px", &s.saliency.stride_px)
      .Add("edge_jump_m", &s.saliency.edge_jump_m)
      .Add("cell_m", &s.saliency.cell_m)
      .Add("max_regions", &s.saliency.max_regions);
  ConfigKeys pipeline;
  pipeline.Add("frames_in_flight", &s.frames_in_flight).Add("threads", &s.threads);
  ConfigKeys lcm;
  lcm.Add("url", &s.bus.url)
      .Add("channel_prefix", &s.bus.channel_prefix)
      .Add("commands", &s.bus.commands)
      .Add("max_fovea_distance_m", &s.bus.max_fovea_distance_m);
  ConfigKeys robot;
  robot.Add("enabled", &s.bus.to_robot_frame)
      .Add("name", &s.bus.robot_frame)
      .Add("translation_m", &robot_translation)
      .Add("rotation", &robot_rotation);
  ConfigKeys service;
  service.Add("log_level", &s.log_level)
      .Add("status_period_s", &s.status_period_s)
      .Add("summary", &s.summary);

  if (!ApplyConfigFile(path, top,
                       {{"recognition", RecognitionKeys(&s.recognition)},
                        {"fovea", FoveaKeys(&s.fovea)},
                        {"attention", attention},
                        {"saliency", saliency},
                        {"pipeline", pipeline},
                        {"lcm", lcm},
                        {"robot_frame", robot},
                        {"service", service}},
                       error))
    return false;
  a.growth_kind = static_cast<GrowthKind>(growth_kind);
  a.fallback = static_cast<LostFallback>(fallback);
  if (std::abs(robot_rotation.norm() - 1.0f) > 1e-3f) {
    *error = path + ": key 'robot_frame.rotation': must be a unit quaternion [w, x, y, z]";
    return false;
  }
  s.bus.robot_from_camera = Eigen::Isometry3f::Identity();
  s.bus.robot_from_camera.translate(robot_translation);
  s.bus.robot_from_camera.rotate(robot_rotation.normalized());
  std::string why;
  if (!s.IsValid(&why)) {
    *error = path + ": " + why;
    return false;
  }
  *settings = s;
  return true;
}

}  // namespace saccade
