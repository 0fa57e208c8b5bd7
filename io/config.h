// Strict YAML configuration: every key must be known, of the right type and in range; errors
// name the file, the key and the reason.
#pragma once

#include "core/foveation.h"
#include "core/recognition.h"
#include "core/scenario.h"

#include <string>

namespace saccade {

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

/// A synthetic scenario file: `preset: NAME` (required, the starting point), then any of
/// name, frames, rate_hz, seed, table_height_m, occluded_from, occluded_frames, and the
/// sections target_motion / camera_motion (Trajectory fields; kind: static | linear | circular
/// | leave-return), noise (KinectNoise fields) and clutter (a list that replaces the preset's:
/// {kind: box, half_size_m: [x, y, z], xz_m: [x, z], yaw_rad} or {kind: sphere, radius_m,
/// xz_m}). Strict as LoadRecognitionConfig.
bool LoadScenario(const std::string& path, Scenario* scenario, std::string* error);

}  // namespace saccade
