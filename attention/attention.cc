#include "attention/attention.h"

#include "core/check.h"
#include "core/fail.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace saccade {
namespace {

// The first of `places` farther than `radius_m` from every place in `seen`.
std::vector<Eigen::Vector3f>::const_iterator FirstFarFrom(
    const std::vector<Eigen::Vector3f>& places, const std::vector<Eigen::Vector3f>& seen,
    float radius_m) {
  return std::find_if(places.begin(), places.end(), [&](const Eigen::Vector3f& p) {
    return std::none_of(seen.begin(), seen.end(),
                        [&](const Eigen::Vector3f& v) { return (p - v).norm() < radius_m; });
  });
}

}  // namespace

bool AttentionOptions::IsValid(std::string* error) const {
  const auto finite = [](float v) { return std::isfinite(v); };
  if (!finite(growth_min_m) || growth_min_m < 0) return Fail(error, "growth_min_m must be >= 0");
  if (!finite(growth_max_m) || growth_max_m < growth_min_m)
    return Fail(error, "growth_max_m must be >= growth_min_m");
  if (!finite(growth_step) || growth_step <= 0) return Fail(error, "growth_step must be > 0");
  if (growth_kind == GrowthKind::kMultiplicative && growth_step <= 1)
    return Fail(error, "growth_step must be > 1 when growth is multiplicative");
  if (!finite(growth_floor_m) || growth_floor_m <= 0)
    return Fail(error, "growth_floor_m must be > 0");
  if (!finite(saccade_region_m) || saccade_region_m <= 0)
    return Fail(error, "saccade_region_m must be > 0");
  if (max_candidate_visits < 0 || max_candidate_visits > 1000)
    return Fail(error, "max_candidate_visits must be in [0, 1000]");
  if (looks_per_frame < 1 || looks_per_frame > 16)
    return Fail(error, "looks_per_frame must be in [1, 16]");
  if (!finite(acquire_confidence) || acquire_confidence < 0 || acquire_confidence > 1)
    return Fail(error, "acquire_confidence must be in [0, 1]");
  if (!finite(tentative_min_confidence) || tentative_min_confidence < 0 ||
      tentative_min_confidence > 1)
    return Fail(error, "tentative_min_confidence must be in [0, 1]");
  if (!finite(challenge_margin) || challenge_margin < 0 || challenge_margin > 1)
    return Fail(error, "challenge_margin must be in [0, 1]");
  if (!finite(land_on_candidate_m) || land_on_candidate_m < 0)
    return Fail(error, "land_on_candidate_m must be >= 0");
  if (!finite(land_stay_m) || land_stay_m < 0) return Fail(error, "land_stay_m must be >= 0");
  if (max_targets < 1) return Fail(error, "max_targets must be >= 1");
  if (!finite(same_target_m) || same_target_m <= 0) return Fail(error, "same_target_m must be > 0");
  if (!finite(predict_max_horizon_s) || predict_max_horizon_s < 0)
    return Fail(error, "predict_max_horizon_s must be >= 0");
  if (!finite(velocity_smoothing) || velocity_smoothing <= 0 || velocity_smoothing > 1)
    return Fail(error, "velocity_smoothing must be in (0, 1]");
  return true;
}

Eigen::Vector3f LandOnCandidate(const Eigen::Vector3f& aim_m,
                                const std::vector<Eigen::Vector3f>& places, float reach_m,
                                float stay_m) {
  float nearest = reach_m;
  for (const Eigen::Vector3f& p : places) nearest = std::min(nearest, (p - aim_m).norm());
  if (nearest <= stay_m) return aim_m;
  for (const Eigen::Vector3f& p : places)  // best first: the best within reach
    if ((p - aim_m).norm() <= reach_m) return p;
  return aim_m;
}

Eigen::Vector3f LandGiven(const Fixation& f, const std::vector<Eigen::Vector3f>& places,
                          float reach_m, float stay_m) {
  const bool near = std::any_of(places.begin(), places.end(), [&](const Eigen::Vector3f& p) {
    return (p - f.fovea_m).norm() <= reach_m;
  });
  if (near || f.aimed || places.empty() || reach_m <= 0)
    return LandOnCandidate(f.fovea_m, places, reach_m, stay_m);
  return places.front();
}

std::vector<Eigen::Vector3f> Looks::Take(
    const Eigen::Vector3f& first_m, const std::vector<Eigen::Vector3f>& places,
    std::vector<Detection>* found,
    const std::function<void(const Eigen::Vector3f&, std::vector<Detection>*)>& look,
    const std::function<bool()>& may_look) const {
  std::vector<Eigen::Vector3f> looked, near = seen;
  near.push_back(first_m);
  const auto enough = [&](const Detection& d) {
    return d.confidence < 0 || d.confidence >= enough_confidence;
  };
  while (static_cast<int>(looked.size()) < left &&
         std::none_of(found->begin(), found->end(), enough)) {
    const auto pick = FirstFarFrom(places, near, radius_m);
    if (pick == places.end() || (may_look && !may_look())) break;
    looked.push_back(*pick);
    near.push_back(*pick);
    const std::size_t before = found->size();
    look(*pick, found);
    // An object two looks saw is kept once: its more confident sighting.
    const auto same = [&](const Detection& a, const Detection& b) {
      return a.model == b.model && (a.centroid_m - b.centroid_m).norm() < radius_m;
    };
    std::vector<bool> drop(found->size(), false);
    for (std::size_t i = before; i < found->size(); ++i)
      for (std::size_t j = 0; j < before; ++j)
        if (!drop[j] && same((*found)[i], (*found)[j]))
          drop[(*found)[i].confidence > (*found)[j].confidence ? j : i] = true;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < found->size(); ++i)
      if (!drop[i]) (*found)[kept++] = std::move((*found)[i]);
    found->resize(kept);
  }
  return looked;
}

bool FollowsTentative(const Fixation& f) {
  return f.mode == AttentionMode::kTracking && f.reason.rfind("tentative", 0) == 0;
}

Eigen::Vector3f Attention::Target::PredictedAt(double time_s) const {
  return position_m + velocity_mps * static_cast<float>(std::max(0.0, time_s - last_seen_s));
}

Attention::Attention(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m)
    : options_(options) {
  SACCADE_CHECK_VALID(options);
  Reset(initial_fovea_m);
}

void Attention::Reset(const Eigen::Vector3f& fovea_m, const std::string& reason, bool aimed) {
  const std::int64_t seq = current_.frame_seq;
  const double time_s = current_.time_s;
  current_ = Fixation{};
  current_.frame_seq = seq;
  current_.time_s = time_s;
  current_.fovea_m = fovea_m;
  current_.growth_m = options_.growth_min_m;
  current_.mode = AttentionMode::kSearching;
  current_.reason = reason;
  targets_.clear();
  visited_.clear();
  saccading_ = false;
  candidate_visits_ = 0;
  has_tentative_ = false;
  current_.lands = true;
  current_.aimed = aimed;
}

void Attention::SetOptions(const AttentionOptions& options) {
  options_ = options;
  current_.growth_m = std::clamp(current_.growth_m, options_.growth_min_m, options_.growth_max_m);
  if (!options_.predict) {
    current_.velocity_mps.setZero();
    for (Target& t : targets_) t.velocity_mps.setZero();
  }
  // Fewer targets allowed: keep the followed one and the oldest others.
  while (static_cast<int>(targets_.size()) > options_.max_targets) {
    auto drop = std::find_if(targets_.rbegin(), targets_.rend(),
                             [&](const Target& t) { return t.id != current_.target; });
    targets_.erase(std::next(drop).base());
  }
  current_.num_targets = static_cast<int>(targets_.size());
}

Attention::Target* Attention::Find(int id) {
  for (Target& t : targets_)
    if (t.id == id) return &t;
  return nullptr;
}

void Attention::See(Target* target, const Detection& s, double time_s) {
  const double dt = time_s - target->last_seen_s;
  if (options_.predict && dt > 0) {
    const Eigen::Vector3f v = (s.centroid_m - target->position_m) / static_cast<float>(dt);
    const float a = target->has_velocity ? options_.velocity_smoothing : 1.0f;
    target->velocity_mps = a * v + (1 - a) * target->velocity_mps;
    target->has_velocity = true;
  }
  target->position_m = s.centroid_m;
  target->last_seen_s = time_s;
  target->confidence = s.confidence;
}

bool Attention::Qualifies(const Detection& s) const {
  return s.confidence < 0 || s.confidence >= options_.acquire_confidence;
}

// While nothing is followed, the most confident sighting too weak to start a target is kept:
// once the candidates are visited, the search follows it rather than nothing.
void Attention::Remember(const std::vector<Detection>& sightings, const std::vector<bool>& used) {
  if (current_.target >= 0 && Find(current_.target)) return;
  for (std::size_t i = 0; i < sightings.size(); ++i) {
    if (used[i] || Qualifies(sightings[i])) continue;
    if (!has_tentative_ || sightings[i].confidence > tentative_.confidence) {
      tentative_ = sightings[i];
      tentative_.correspondences.clear();
      has_tentative_ = true;
    }
  }
}

// Every target but the followed one takes the nearest unclaimed sighting of its model within
// same_target_m of where it should be; the followed target then takes the remaining sighting
// nearest the fovea, however far (the paper's rule: it may have moved while lost); what is left
// becomes new targets, nearest the fovea first, while there is room.
void Attention::Associate(double time_s, const std::vector<Detection>& sightings,
                          bool* attended_seen) {
  std::vector<bool> used(sightings.size(), false);
  const auto nearest = [&](int model, const Eigen::Vector3f& to, float max_distance) {
    int best = -1;
    float best_d = max_distance;
    for (std::size_t i = 0; i < sightings.size(); ++i) {
      if (used[i] || (model >= 0 && sightings[i].model != model)) continue;
      const float d = (sightings[i].centroid_m - to).norm();
      if (d <= best_d) best = static_cast<int>(i), best_d = d;
    }
    return best;
  };
  for (Target& t : targets_) {
    if (t.id == current_.target) continue;
    const int i = nearest(t.model, t.PredictedAt(time_s), options_.same_target_m);
    if (i < 0) continue;
    used[i] = true;
    See(&t, sightings[i], time_s);
  }
  const Eigen::Vector3f fovea = current_.FoveaAt(time_s, options_.predict_max_horizon_s);
  constexpr float kAnyDistance = std::numeric_limits<float>::infinity();
  *attended_seen = false;
  challenged_ = false;
  if (Target* followed = Find(current_.target)) {
    int i = nearest(followed->model, fovea, kAnyDistance);
    // A clearly more confident sighting of its model elsewhere takes the target over.
    if (followed->confidence >= 0) {
      float bar =
          std::max(options_.acquire_confidence, followed->confidence + options_.challenge_margin);
      for (std::size_t j = 0; j < sightings.size(); ++j) {
        if (used[j] || static_cast<int>(j) == i || sightings[j].model != followed->model) continue;
        if (sightings[j].confidence >= bar) i = static_cast<int>(j), bar = sightings[j].confidence;
      }
      challenged_ = i >= 0 &&
                    (sightings[i].centroid_m - followed->PredictedAt(time_s)).norm() >
                        options_.same_target_m &&
                    sightings[i].confidence >= followed->confidence + options_.challenge_margin;
      if (challenged_) followed->velocity_mps.setZero(), followed->has_velocity = false;
    }
    if (i >= 0) {
      used[i] = true;
      See(followed, sightings[i], time_s);
      *attended_seen = true;
    }
  }
  Remember(sightings, used);
  // Only sightings confident enough start a target (acquire_confidence).
  for (std::size_t i = 0; i < sightings.size(); ++i) used[i] = used[i] || !Qualifies(sightings[i]);
  while (static_cast<int>(targets_.size()) < options_.max_targets) {
    const int i = nearest(-1, fovea, kAnyDistance);
    if (i < 0) break;
    used[i] = true;
    targets_.push_back(NewTarget(sightings[i], time_s));
  }
}

void Attention::Follow(const Target& target, double time_s, const char* reason, Fixation* next) {
  visited_.clear();  // a target to follow ends any search
  saccading_ = false;
  candidate_visits_ = 0;
  has_tentative_ = false;
  next->lands = false;
  next->fovea_m = target.PredictedAt(time_s);
  next->velocity_mps = target.velocity_mps;
  next->growth_m = options_.growth_min_m;
  next->mode = AttentionMode::kTracking;
  next->searched_frames = 0;
  next->target = target.id;
  next->model = target.model;
  next->reason = reason;
}

Fixation Attention::Update(std::int64_t frame_seq, double time_s,
                           const std::vector<Detection>& sightings,
                           const std::vector<Eigen::Vector3f>& places) {
  Fixation next = current_;
  ++next.searched_frames;  // Follow sets it back to 0
  next.frame_seq = frame_seq;
  next.time_s = time_s;
  bool attended_seen = false;
  Associate(time_s, sightings, &attended_seen);

  if (attended_seen) {
    const auto it = std::find_if(targets_.begin(), targets_.end(),
                                 [&](const Target& t) { return t.id == current_.target; });
    if (targets_.size() > 1) {  // visit the next target in turn
      const auto after = std::next(it) == targets_.end() ? targets_.begin() : std::next(it);
      Follow(*after, time_s, "alternate", &next);
    } else {
      Follow(*it, time_s, challenged_ ? "challenged" : "detected", &next);
    }
  } else if (current_.target < 0 && !targets_.empty()) {
    // Found while searching with no target: follow the new target nearest the fovea.
    const auto it = std::min_element(targets_.begin(), targets_.end(), [&](auto& a, auto& b) {
      return (a.position_m - current_.fovea_m).squaredNorm() <
             (b.position_m - current_.fovea_m).squaredNorm();
    });
    Follow(*it, time_s, "detected", &next);
  } else {
    Lost(places, &next);
  }
  next.num_targets = static_cast<int>(targets_.size());
  current_ = next;
  return next;
}

// The first of `places` farther than `radius_m` from every place visited in this search.
std::vector<Eigen::Vector3f>::const_iterator Attention::FirstUnvisited(
    const std::vector<Eigen::Vector3f>& places, float radius_m) const {
  return FirstFarFrom(places, visited_, radius_m);
}

// A search's jump: the fovea to `place` at G_min.
void Attention::JumpTo(const Eigen::Vector3f& place, const char* reason, Fixation* next) const {
  next->fovea_m = place;
  next->growth_m = options_.growth_min_m;
  next->mode = AttentionMode::kSearching;
  next->reason = reason;
}

Attention::Target Attention::NewTarget(const Detection& s, double time_s) {
  Target t;
  t.id = next_id_++;
  t.model = s.model;
  t.position_m = s.centroid_m;
  t.last_seen_s = time_s;
  t.confidence = s.confidence;
  return t;
}

// The best candidate not visited in this search (nor where the fovea is): false when none is
// left or the visits are spent.
bool Attention::VisitCandidate(const std::vector<Eigen::Vector3f>& places, Fixation* next) {
  if (candidate_visits_ >= options_.max_candidate_visits) return false;
  if (candidate_visits_ == 0) visited_.clear();
  visited_.push_back(current_.fovea_m);
  const auto pick = FirstUnvisited(places, options_.same_target_m);
  if (pick == places.end()) return false;
  ++candidate_visits_;
  JumpTo(*pick, "candidate", next);
  return true;
}

// The given fovea lands on `landed_m` (the fovea itself: it stays). Landing near it is not one
// of the search's candidate visits; a guess's jump to the frame's best candidate is its first.
void Attention::Land(const Eigen::Vector3f& landed_m, Fixation* f) {
  f->lands = false;
  if (landed_m == f->fovea_m) return;
  visited_.assign(1, f->fovea_m);
  const bool visit = (landed_m - f->fovea_m).norm() > options_.land_on_candidate_m;
  candidate_visits_ += visit;
  JumpTo(landed_m, visit ? "candidate" : "landed", f);
}

Looks Attention::PlanLooks() const {
  Looks looks;
  looks.radius_m = options_.same_target_m;
  looks.enough_confidence = options_.acquire_confidence;
  const bool growing = current_.growth_m > options_.growth_min_m;
  const bool lost = !targets_.empty();  // searched for where it was lost, G growing
  // A command's aim is looked at alone in its frame, as asked.
  if (options_.search != SearchKind::kCandidates || current_.mode != AttentionMode::kSearching ||
      saccading_ || (growing && !lost) || (current_.lands && current_.aimed))
    return looks;
  looks.moves_fovea = !lost;
  looks.left =
      std::min(options_.looks_per_frame - 1, options_.max_candidate_visits - candidate_visits_);
  if (candidate_visits_ > 0) looks.seen = visited_;
  return looks;
}

void Attention::Looked(std::int64_t frame_seq, const Eigen::Vector3f& first_m,
                       const std::vector<Eigen::Vector3f>& looks) {
  if (current_.frame_seq != frame_seq || current_.fovea_m != first_m) return;
  const bool lost = !targets_.empty();
  for (const Eigen::Vector3f& place : looks) {
    if (candidate_visits_ == 0) visited_.clear();
    ++candidate_visits_;
    if (lost) {  // the fovea stays where the target was lost
      visited_.push_back(place);
      continue;
    }
    visited_.push_back(current_.fovea_m);
    JumpTo(place, "candidate", &current_);
  }
}

void Attention::Landed(const Eigen::Vector3f& aim_m, const Eigen::Vector3f& landed_m) {
  if (current_.lands && current_.fovea_m == aim_m) Land(landed_m, &current_);
}

void Attention::Lost(const std::vector<Eigen::Vector3f>& places, Fixation* next) {
  next->velocity_mps.setZero();  // a lost target's fovea stays where it was last seen
  if (current_.mode == AttentionMode::kFullScan) {
    next->reason = "full_scan";
    return;
  }
  // With no target known (a cold start, a reset): candidates first, then the best sighting too
  // weak to start on, then G grows from the last of them. A lost target is searched where it
  // was last seen, as the paper does: it is likeliest to come back there.
  const bool growing = current_.growth_m > options_.growth_min_m || saccading_;
  if (options_.search == SearchKind::kCandidates && !growing && targets_.empty()) {
    // A fovea given from outside and not landed by its frame's recognizer (Landed) lands now.
    if (current_.lands && options_.land_on_candidate_m > 0 && !places.empty()) {
      const Eigen::Vector3f landed =
          LandGiven(current_, places, options_.land_on_candidate_m, options_.land_stay_m);
      Land(landed, next);
      if (landed != current_.fovea_m) return;
    }
    if (VisitCandidate(places, next)) return;
    if (has_tentative_ && tentative_.confidence >= options_.tentative_min_confidence) {
      targets_.assign(1, NewTarget(tentative_, next->time_s));
      Follow(targets_.front(), next->time_s, "tentative", next);
      return;
    }
  }
  if (current_.growth_m < options_.growth_max_m && !saccading_) {
    const float g = current_.growth_m;
    const float grown = options_.growth_kind == GrowthKind::kMultiplicative
                            ? std::max(g, options_.growth_floor_m) * options_.growth_step
                            : g + options_.growth_step;
    next->growth_m = std::min(grown, options_.growth_max_m);
    next->mode = AttentionMode::kSearching;
    next->reason = current_.mode == AttentionMode::kTracking ? "lost" : "grow";
    return;
  }
  // At G_max. With other targets, give this one up and visit the next.
  if (targets_.size() > 1) {
    auto it = std::find_if(targets_.begin(), targets_.end(),
                           [&](const Target& t) { return t.id == current_.target; });
    const int after = static_cast<int>(std::distance(targets_.begin(), it)) %
                      static_cast<int>(targets_.size() - 1);
    targets_.erase(it);
    Follow(targets_[after], next->time_s, "lost", next);
    return;
  }
  if (options_.fallback == LostFallback::kFullScan) {
    next->mode = AttentionMode::kFullScan;
    next->reason = "full_scan";
    return;
  }
  // Saccade: the most salient region not visited in this search (and not where we are).
  visited_.push_back(current_.fovea_m);
  auto pick = FirstUnvisited(places, options_.saccade_region_m);
  if (pick == places.end() && !places.empty()) {  // everything seen once: start over
    visited_.assign(1, current_.fovea_m);
    pick = FirstUnvisited(places, options_.saccade_region_m);
  }
  next->mode = AttentionMode::kSearching;
  if (pick == places.end()) {  // nothing salient at all: keep searching where we are
    next->reason = "grow";
    return;
  }
  saccading_ = true;
  JumpTo(*pick, "saccade", next);
}

}  // namespace saccade
