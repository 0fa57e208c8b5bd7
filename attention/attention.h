// The attention loop of paper §3.4: the fovea jumps to the detected object; while the object
// is lost the fovea's growth factor G grows each frame until it is found again, and past G_max
// the configured fallback takes over. Beyond the paper: several targets are visited in turn,
// one per frame, and an optional constant-velocity predictor leads the fovea. Pure: sightings
// in, one Fixation per frame out. Positions are in the camera frame, metres; times in seconds.
#pragma once

#include "core/fixation.h"
#include "core/schema.h"
#include "core/types.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace saccade {

enum class GrowthKind { kAdditive, kMultiplicative };
enum class LostFallback { kFullScan, kSaccade };
/// How a search starts: visit the frame's candidates (core/candidates.h), best first, before G
/// grows; or grow G from the last fixation at once (the paper).
enum class SearchKind { kCandidates, kGrow };

struct AttentionOptions {
  float growth_min_m = 0.0f;  // G_min, used while tracking (paper: 0)
  float growth_max_m = 1.0f;  // G_max, after which the fallback takes over
  /// Per lost frame: G += step (additive, metres) or G := max(G, growth_floor_m) * step
  /// (multiplicative, a factor > 1).
  GrowthKind growth_kind = GrowthKind::kAdditive;
  float growth_step = 0.1f;
  float growth_floor_m = 0.01f;  // where multiplicative growth starts from when G is 0
  /// Past G_max: search the whole unfoveated frame, or jump to the most salient coarse region
  /// not yet visited in this search (inhibition of return), one region per frame.
  LostFallback fallback = LostFallback::kFullScan;
  /// Two salient regions closer than this are the same region (inhibition of return), metres.
  float saccade_region_m = 0.25f;
  /// The search: candidates first (then G grows), or G grows at once.
  SearchKind search = SearchKind::kCandidates;
  /// Candidates visited per search before G grows from the last of them.
  int max_candidate_visits = 8;
  /// Places a search frame recognizes at (its fovea, then the best candidates not visited),
  /// until one gives a sighting confident enough to follow: a frame costs up to this many
  /// recognitions and an object among them is found in it. 1: one place a frame (the paper).
  int looks_per_frame = 3;
  /// A search starts following a sighting only at this confidence or above (a sighting without
  /// one, from unverified recognition, always qualifies). Below it, the most confident sighting
  /// of the search is remembered and followed once the candidates are visited. 0: follow the
  /// first sighting, as the paper does.
  float acquire_confidence = 0.9f;
  /// The remembered sighting is followed only at this confidence or above; below it the search
  /// goes on (G grows) rather than lock onto the best of poor sightings.
  float tentative_min_confidence = 0.7f;
  /// A fixation given from outside (a command, the initial fovea) lands on the best candidate
  /// within this distance, as a saccade lands on the object near where it was aimed. 0: it
  /// stays where it was given.
  float land_on_candidate_m = 0.25f;
  /// ...unless a candidate lies this near the aim: the fixation is on an object already.
  float land_stay_m = 0.08f;
  /// A followed target gives way to a sighting of its model elsewhere that is at least
  /// acquire_confidence and this much more confident than the target's own last sighting.
  float challenge_margin = 0.15f;
  /// Targets visited in turn, one per frame; 1 follows one target as the paper does.
  int max_targets = 1;
  /// A sighting within this distance of where a target should be is that target, metres.
  float same_target_m = 0.1f;
  /// Constant-velocity predictor: off gives the paper's behaviour.
  bool predict = false;
  float predict_max_horizon_s = 0.2f;  // never lead the fovea by more than this
  float velocity_smoothing = 0.5f;     // weight of the newest velocity estimate, (0, 1]

  bool IsValid(std::string* error) const;
  bool operator==(const AttentionOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const AttentionOptions& o) const { return !(*this == o); }
  /// The keys of the `attention` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("growth_min_m", &growth_min_m);
    a->Visit("growth_max_m", &growth_max_m);
    a->Choice(
        "growth", &growth_kind,
        {{"additive", GrowthKind::kAdditive}, {"multiplicative", GrowthKind::kMultiplicative}});
    a->Visit("growth_step", &growth_step);
    a->Visit("growth_floor_m", &growth_floor_m);
    a->Choice("fallback", &fallback,
              {{"full_scan", LostFallback::kFullScan}, {"saccade", LostFallback::kSaccade}});
    a->Visit("saccade_region_m", &saccade_region_m);
    a->Choice("search", &search,
              {{"candidates", SearchKind::kCandidates}, {"grow", SearchKind::kGrow}});
    a->Visit("max_candidate_visits", &max_candidate_visits);
    a->Visit("looks_per_frame", &looks_per_frame);
    a->Visit("acquire_confidence", &acquire_confidence);
    a->Visit("tentative_min_confidence", &tentative_min_confidence);
    a->Visit("challenge_margin", &challenge_margin);
    a->Visit("land_on_candidate_m", &land_on_candidate_m);
    a->Visit("land_stay_m", &land_stay_m);
    a->Visit("max_targets", &max_targets);
    a->Visit("same_target_m", &same_target_m);
    a->Visit("predict", &predict);
    a->Visit("predict_max_horizon_s", &predict_max_horizon_s);
    a->Visit("velocity_smoothing", &velocity_smoothing);
  }
};

/// Where a fixation aimed at `aim_m` lands: the first (best) of `places` within `reach_m`, or
/// the aim itself when none is that near or one is within `stay_m` of it (it is on an object
/// already).
Eigen::Vector3f LandOnCandidate(const Eigen::Vector3f& aim_m,
                                const std::vector<Eigen::Vector3f>& places, float reach_m,
                                float stay_m = 0);

/// Where a given fovea (`f.lands`) lands: LandOnCandidate over `places` (best first); a guess
/// (not `f.aimed`) with no candidate within `reach_m` lands on the best of them.
Eigen::Vector3f LandGiven(const Fixation& f, const std::vector<Eigen::Vector3f>& places,
                          float reach_m, float stay_m);

/// A search frame's further looks (AttentionOptions::looks_per_frame), planned from the search
/// as it stood when the frame was foveated (Attention::PlanLooks).
struct Looks {
  std::vector<Eigen::Vector3f> seen;  // places visited in this search
  int left = 0;                       // looks the frame may take after its first
  float radius_m = 0.1f;              // a place this near a seen one is seen (same_target_m)
  float enough_confidence = 0.9f;     // a sighting this confident ends the frame's looks
  /// A search from nothing moves its fovea to the last look; a lost target's search keeps its
  /// fovea where the target was lost (G grows there) and looks at candidates beside it.
  bool moves_fovea = true;
  /// Recognizes the frame at further places after its first look at `first_m` whose
  /// sightings are in `found`: while none of them is enough_confidence (or unverified) and
  /// looks are left, at the best of `places` not seen yet. `look(place, &found)` recognizes
  /// there and appends its sightings; one of a model within radius_m of a more confident one
  /// of that model is the same object, kept once. `may_look`, when given, is asked before
  /// each further look: false ends the frame's looks there (its time is spent). Returns the
  /// places looked at, in order.
  std::vector<Eigen::Vector3f> Take(
      const Eigen::Vector3f& first_m, const std::vector<Eigen::Vector3f>& places,
      std::vector<Detection>* found,
      const std::function<void(const Eigen::Vector3f&, std::vector<Detection>*)>& look,
      const std::function<bool()>& may_look = {}) const;
};

/// True when attention follows the best instance of a search from nothing, one that started
/// no track (reason "tentative"): saccaded lets a track start from it below the bar.
bool FollowsTentative(const Fixation& f);

/// Serial state machine; call Update once per frame, in frame order. Not thread-safe.
class Attention {
 public:
  Attention(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m);

  /// Digests one frame: its sightings (every model's instances) and where to look next when
  /// searching, best first: the frame's candidates (search: candidates) or, for the saccade
  /// fallback, the salient regions of its coarse level.
  Fixation Update(std::int64_t frame_seq, double time_s, const std::vector<Detection>& sightings,
                  const std::vector<Eigen::Vector3f>& places = {});
  /// A frame foveated at the given fovea `aim_m` (Fixation::lands) was landed by its
  /// recognizer on `landed_m` (LandGiven over that frame's candidates) and recognized
  /// there: the search counts that as its landing. Call before that frame's Update. Ignored
  /// when the landing is done already or the fovea was given again since (a command).
  void Landed(const Eigen::Vector3f& aim_m, const Eigen::Vector3f& landed_m);
  /// The looks a frame foveated at the current fixation may take besides its first, at the
  /// frame's candidates (attention.search: candidates): a search with no target before G
  /// grows, and a lost target's search while G grows where it was lost (an object that moved
  /// while unseen is found where it went); none on a command's aim (Fixation::aimed) not
  /// landed yet, none past G_max.
  Looks PlanLooks() const;
  /// The frame foveated at the fixation of `frame_seq`, first recognized at `first_m` (the
  /// fovea, or where it landed: call Landed first), also recognized at `looks` (Looks::Take):
  /// each is one of the search's candidate visits, the fovea ending on the last (a search from
  /// nothing; a lost target's fovea stays). Call before
  /// that frame's Update. Ignored when the fixation changed since (a command).
  void Looked(std::int64_t frame_seq, const Eigen::Vector3f& first_m,
              const std::vector<Eigen::Vector3f>& looks);
  /// Forgets every target: searching around `fovea_m` with G_min. `reason` goes in the record;
  /// `aimed`: the fovea is an aim (a command), not a guess (Fixation::aimed).
  void Reset(const Eigen::Vector3f& fovea_m, const std::string& reason = "reset",
             bool aimed = false);
  /// New options (a reloaded config); targets are kept, G is clamped into the new range.
  void SetOptions(const AttentionOptions& options);
  const Fixation& current() const { return current_; }
  const AttentionOptions& options() const { return options_; }

 private:
  struct Target {
    int id = 0;
    int model = 0;
    Eigen::Vector3f position_m = Eigen::Vector3f::Zero();  // at last_seen_s
    Eigen::Vector3f velocity_mps = Eigen::Vector3f::Zero();
    bool has_velocity = false;  // seen twice with the predictor on
    double last_seen_s = 0;
    float confidence = -1;  // of its last sighting
    Eigen::Vector3f PredictedAt(double time_s) const;
  };

  Target* Find(int id);
  Target NewTarget(const Detection& s, double time_s);
  std::vector<Eigen::Vector3f>::const_iterator FirstUnvisited(
      const std::vector<Eigen::Vector3f>& places, float radius_m) const;
  void JumpTo(const Eigen::Vector3f& place, const char* reason, Fixation* next) const;
  void Associate(double time_s, const std::vector<Detection>& sightings, bool* attended_seen);
  void See(Target* target, const Detection& s, double time_s);
  void Follow(const Target& target, double time_s, const char* reason, Fixation* next);
  void Lost(const std::vector<Eigen::Vector3f>& places, Fixation* next);
  bool VisitCandidate(const std::vector<Eigen::Vector3f>& places, Fixation* next);
  void Land(const Eigen::Vector3f& landed_m, Fixation* f);
  bool Qualifies(const Detection& s) const;
  void Remember(const std::vector<Detection>& sightings, const std::vector<bool>& used);

  AttentionOptions options_;
  Fixation current_;
  std::vector<Target> targets_;  // by id, oldest first
  int next_id_ = 0;
  std::vector<Eigen::Vector3f> visited_;  // saccade fallback: regions seen in this search
  bool saccading_ = false;                // the fallback is jumping between salient regions
  /// This search's candidate visits, and its most confident sighting below acquire_confidence.
  int candidate_visits_ = 0;
  bool has_tentative_ = false;
  bool challenged_ = false;  // this frame's sighting of the followed target took it elsewhere
  Detection tentative_;
};

}  // namespace saccade
