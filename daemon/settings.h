// saccaded's configuration: every parameter, loaded strictly from one YAML file
// (configs/saccaded.yaml documents each key with its unit).
#pragma once

#include "attention/attention.h"
#include "attention/tracks.h"
#include "core/candidates.h"
#include "core/foveation.h"
#include "core/pictures/preview.h"
#include "core/recognition.h"
#include "core/saliency.h"
#include "io/base/log.h"
#include "io/lcm/bus.h"
#include "io/ros2/mcap_log.h"
#include "io/ros2/ros2.h"

#include <string>
#include <vector>

namespace saccade {

/// How frames go through the tracker (the `pipeline` section).
/// Where frames come from: `source: SPEC` alone, or this section.
struct SourceOptions {
  std::string spec = "openni2://";  // a frame source spec (docs/SOURCES.md)
  /// A live camera that is not there at start is waited for this long, with the back-off of a
  /// reconnect, STATUS saying "waiting for device" (0: fail at once, for scripts).
  double wait_at_start_s = 60;

  bool IsValid(std::string* error) const;
  bool operator==(const SourceOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const SourceOptions& o) const { return !(*this == o); }
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("spec", &spec);
    a->Visit("wait_at_start_s", &wait_at_start_s);
  }
};

struct PipelineOptions {
  /// Frames in the pipeline at once, in [1, 16]. 1 gives the lowest latency when a frame fits
  /// in the sensor period (recognition already uses every core); 2 overlaps frames for
  /// throughput.
  int frames_in_flight = 1;
  int threads = 0;  // worker threads; 0: one per core
  /// A live source's search frame takes its further looks (attention.looks_per_frame) only
  /// while they end before the next frame arrives (LooksUntilNs): the looks left are the next
  /// frame's, and no frame waits or is dropped for them. false: every look, whatever it costs.
  /// A source read on demand (rate 0) waits for the pipeline and takes every look either way.
  bool looks_keep_pace = true;

  bool IsValid(std::string* error) const;
  bool operator==(const PipelineOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const PipelineOptions& o) const { return !(*this == o); }
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("frames_in_flight", &frames_in_flight);
    a->Visit("threads", &threads);
    a->Visit("looks_keep_pace", &looks_keep_pace);
  }
};

/// The service's own behaviour (the `service` section).
struct ServiceOptions {
  // line: one human line per status period on stdout; auto: line when stdout is a terminal
  // (saccaded decides, and not with --quiet; any other program takes auto as off).
  enum class Summary { kOff, kLine, kAuto };
  LogLevel log_level = LogLevel::kInfo;
  double status_period_s = 1.0;  // SACCADE_STATUS period, >= 0.05
  Summary summary = Summary::kAuto;

  bool IsValid(std::string* error) const;
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Choice("log_level", &log_level,
              {{"debug", LogLevel::kDebug},
               {"info", LogLevel::kInfo},
               {"warning", LogLevel::kWarning},
               {"error", LogLevel::kError}});
    a->Visit("status_period_s", &status_period_s);
    a->Choice("summary", &summary,
              {{"off", Summary::kOff}, {"line", Summary::kLine}, {"auto", Summary::kAuto}});
  }
};

/// Saccade's recognition defaults with saccaded's search budget: 1200 keypoints never cut a
/// fovea at G = 0 on the cross-capture benchmark (protocol (a) unchanged, 171/212) and bound a
/// grown fovea's frame near 30 ms on this machine (docs/BENCHMARKS.md).
inline RecognitionOptions DaemonRecognitionOptions() {
  RecognitionOptions o;
  o.max_scene_keypoints = 1200;
  return o;
}

struct DaemonSettings {
  SourceOptions source;
  /// Model PCD files, or synthetic:target (the synthetic Kinect's target, for demos).
  std::vector<std::string> models;
  Eigen::Vector3f initial_fovea_m{0.0f, 0.0f, 1.0f};  // camera frame, before any detection
  RecognitionOptions recognition = DaemonRecognitionOptions();
  FoveaOptions fovea;  // growth_m is attention's to set: a file may not
  AttentionOptions attention;
  CandidateOptions candidates;  // where a search looks first (attention.search: candidates)
  TrackingOptions tracking;
  SaliencyOptions saliency;
  PipelineOptions pipeline;
  BusOptions bus;
  ServiceOptions service;
  PreviewOptions preview;  // PREFIX_PREVIEW, for viewers (saccade view)
  Ros2Options ros2;        // the same messages on ROS 2's wire (docs/ROS2.md)
  McapLogOptions log;      // and in an MCAP file

  bool IsValid(std::string* error) const;
  bool operator==(const DaemonSettings& o) const { return SameFields(*this, o); }
  /// The keys of configs/saccaded.yaml (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Section("source", &source);
    a->Visit("model", &models);
    a->Visit("initial_fovea_m", &initial_fovea_m);
    a->Section("recognition", &recognition);
    a->Section("fovea", &fovea);
    a->Section("attention", &attention);
    a->Section("candidates", &candidates);
    a->Section("tracking", &tracking);
    a->Section("saliency", &saliency);
    a->Section("pipeline", &pipeline);
    a->Section("lcm", &bus);
    a->Section("robot_frame", &bus.robot);
    a->Section("service", &service);
    a->Section("preview", &preview);
    a->Section("ros2", &ros2);
    a->Section("log", &log);
  }
};

/// The paper's defaults (Tables 1 and 2) with Saccade's service settings. A default-constructed
/// DaemonSettings holds Saccade's own (configs/saccaded.yaml).
DaemonSettings PaperDefaults();

/// Applies the file over `settings` strictly: "FILE: key 'a.b': reason" on an unknown key, a
/// wrong type or a value out of range.
bool LoadDaemonSettings(const std::string& path, DaemonSettings* settings, std::string* error);

}  // namespace saccade
