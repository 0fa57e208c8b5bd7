// saccaded's configuration: every parameter, loaded strictly from one YAML file
// (configs/saccaded.yaml documents each key with its unit).
#pragma once

#include "attention/attention.h"
#include "core/foveation.h"
#include "core/recognition.h"
#include "core/saliency.h"
#include "io/bus.h"

#include <string>
#include <vector>

namespace saccade {

struct DaemonSettings {
  std::string source = "openni2://";  // a frame source spec (docs/SOURCES.md)
  /// Model PCD files, or synthetic:target (the synthetic Kinect's target, for demos).
  std::vector<std::string> models;
  Eigen::Vector3f initial_fovea_m{0.0f, 0.0f, 1.0f};  // camera frame, before any detection
  RecognitionOptions recognition;
  FoveaOptions fovea;
  AttentionOptions attention;
  SaliencyOptions saliency;
  /// Frames in the pipeline at once (>= 1). 1 gives the lowest latency when a frame fits in the
  /// sensor period (recognition already uses every core); 2 overlaps frames for throughput.
  int frames_in_flight = 1;
  int threads = 0;  // worker threads; 0: one per core
  BusOptions bus;
  std::string log_level = "info";  // debug | info | warning | error
  double status_period_s = 1.0;    // SACCADE_STATUS period
  std::string summary = "off";     // off | line: one human line per status period on stdout

  bool IsValid(std::string* error) const;
};

/// The paper's defaults (Tables 1 and 2) with Saccade's service settings. A default-constructed
/// DaemonSettings holds Saccade's own (configs/saccaded.yaml).
DaemonSettings PaperDefaults();

/// Applies the file over `settings` strictly: "FILE: key 'a.b': reason" on an unknown key, a
/// wrong type or a value out of range.
bool LoadDaemonSettings(const std::string& path, DaemonSettings* settings, std::string* error);

}  // namespace saccade
