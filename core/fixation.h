// Where attention looks: the value the attention loop produces once per frame, the fovea the
// next frame is foveated at, published as SACCADE_FIXATION and written to the fixation log.
// Positions are in the camera frame, metres; times in seconds.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>

namespace saccade {

/// TRACKING: the fovea follows a target; SEARCHING: the target is lost and G grows;
/// FULL_SCAN: past G_max, the whole frame is searched. The values are fixation_t's constants.
enum class AttentionMode { kTracking = 0, kSearching = 1, kFullScan = 2 };
/// "TRACKING", "SEARCHING" or "FULL_SCAN" (fixation_t's mode_name).
const char* ModeName(AttentionMode mode);

/// One frame's fixation: where the next frame will be foveated, and why.
struct Fixation {
  std::int64_t frame_seq = -1;  // the frame whose sightings produced this fixation
  double time_s = 0;            // that frame's capture time; fovea_m is valid at this time
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();
  /// The followed target's velocity when the predictor is on, else zero.
  Eigen::Vector3f velocity_mps = Eigen::Vector3f::Zero();
  float growth_m = 0;  // G, applied on every axis
  /// Frames searched since the target was lost (or since a reset): 0 while following one. A
  /// budgeted search (RecognitionOptions::max_scene_keypoints) takes its window from it.
  int searched_frames = 0;
  /// The budgeted search's window for the next frame (SceneQuery::search_phase).
  int SearchPhase() const { return searched_frames > 0 ? searched_frames - 1 : 0; }
  AttentionMode mode = AttentionMode::kSearching;
  int target = -1;      // id of the followed target (stable across frames), -1 when none
  int model = -1;       // that target's model index, -1 when none
  int num_targets = 0;  // targets attention knows of
  /// Why it is where it is: detected, alternate, lost, grow, full_scan, saccade, command, reset.
  std::string reason;
  /// The fovea was given from outside (the initial fovea, a reset, a command) and has not
  /// landed yet: the next frame lands it on the best candidate near it before recognizing
  /// (attention/attention.h, LandGiven and Attention::Landed), so that landing costs no frame.
  bool lands = false;
  /// ...and it was aimed (a command's SET_FOVEA): with no candidate near, it stays where aimed
  /// for a frame. Not aimed (the initial fovea, a reset), it is a guess: with no candidate near,
  /// it lands on the frame's best candidate.
  bool aimed = false;

  /// Where to foveate a frame captured at `capture_time_s`: the fovea moved on by the velocity
  /// for at most `max_horizon_s` (the predictor's lead; zero velocity: the fovea itself).
  Eigen::Vector3f FoveaAt(double capture_time_s, double max_horizon_s) const;
};

}  // namespace saccade
