#include "core/library.h"

#include "core/check.h"

#include <algorithm>
#include <chrono>

namespace saccade {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Where instances of two models claim one place, each is ranked by its confidence plus this
// share of its colour agreement (none without colour): look-alikes that verification scores
// alike (a plain mug and a printed one, 0.97-0.98) differ in colour, which the confidence weighs
// with the rest. Chosen on alternate captures of the library benchmark with all 27 models (0.5
// to 1 alike there, 0.25 and 1.5 a little worse; 0.5 the lowest of those) and checked on the
// others (docs/RESULTS.md, "Look-alikes told apart by colour").
constexpr float kArbitrationColourWeight = 0.5f;

// Models describe a frame alike when their scene radii are the same.
bool SameSceneRadii(const RecognitionOptions& a, const RecognitionOptions& b) {
  return a.scene_shot_radius_m == b.scene_shot_radius_m &&
         a.scene_lrf_radius_m == b.scene_lrf_radius_m &&
         a.scene_keypoint_radius_m == b.scene_keypoint_radius_m;
}

}  // namespace

// Models of one set of scene radii: one description of a frame, one index over all their
// descriptors (model after model, model m's rows from first_row[m]).
struct Library::Group {
  RecognitionOptions options;  // the first model's fitted options: its scene radii are all's
  std::vector<std::size_t> models;
  std::vector<int> first_row;  // per entry of `models`, then the total
  std::unique_ptr<ShotIndex> index;
};

Library::Library(std::vector<const ModelDescription*> models, const RecognitionOptions& options)
    : models_(std::move(models)) {
  for (std::size_t m = 0; m < models_.size(); ++m) {
    const RecognitionOptions fitted = RadiiForModel(options, models_[m]->scale());
    auto g = std::find_if(groups_.begin(), groups_.end(),
                          [&](const Group& g) { return SameSceneRadii(g.options, fitted); });
    if (g == groups_.end()) {
      groups_.emplace_back();
      g = groups_.end() - 1;
      g->options = fitted;
      g->first_row.push_back(0);
    }
    g->models.push_back(m);
    g->first_row.push_back(g->first_row.back() + int(models_[m]->descriptors().size()));
  }
  for (Group& g : groups_) {
    std::vector<float> shots;
    shots.reserve(std::size_t(g.first_row.back()) * kShotLength);
    for (std::size_t m : g.models) {
      const std::vector<float>& s = models_[m]->descriptors().shot;
      shots.insert(shots.end(), s.begin(), s.end());
    }
    g.index = std::make_unique<ShotIndex>(std::move(shots), options);
  }
}

Library::~Library() = default;
Library::Library(Library&&) noexcept = default;
Library& Library::operator=(Library&&) noexcept = default;
std::size_t Library::Groups() const { return groups_.size(); }

float ArbitrationScore(const Detection& d) {
  return d.confidence + kArbitrationColourWeight * std::max(0.0f, d.colour_agreement);
}

bool ClaimSamePlace(const Detection& a, float size_a, const Detection& b, float size_b) {
  return (a.centroid_m - b.centroid_m).norm() < 0.5f * std::min(size_a, size_b);
}

LibraryResult RecognizeLibrary(const Library& library, const Cloud& scene, const SceneQuery& query,
                               const RecognitionOptions& given, const std::vector<bool>& which,
                               const ParallelFor& parallel_for, std::string* error) {
  SACCADE_CHECK_VALID(given);
  SACCADE_CHECK_VALID(query.fovea);
  LibraryResult out;
  out.per_model.resize(library.size());
  const auto wanted = [&](std::size_t m) { return which.empty() || which[m]; };
  SceneNormals normals;  // the groups' descriptions read one set of normals
  for (const Library::Group& g : library.groups_) {
    if (std::none_of(g.models.begin(), g.models.end(), wanted)) continue;
    const auto t_total = Clock::now();
    // The options this search was given (a re-check's smaller keypoint budget, say), with the
    // group's radii: its models' radii are one.
    const RecognitionOptions options = RadiiForModel(given, library.model(g.models[0]).scale());
    std::optional<SceneDescription> described =
        DescribeScene(scene, query, options, parallel_for, error, &normals);
    if (!described) break;  // the scene has no finite point: the same for every group
    ++out.scene_descriptions;
    for (const auto& [stage, ms] : described->stats.stage_ms) out.describe_ms += ms;

    // Each scene descriptor's nearest descriptor of any of the group's models.
    auto t = Clock::now();
    const Descriptors& scene_desc = described->descriptors;
    const float max_d2 = options.max_descriptor_sqr_distance;
    std::vector<std::pair<int, float>> nearest(scene_desc.size());
    parallel_for(scene_desc.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        nearest[i] = g.index->Nearest(scene_desc.Row(i), max_d2);
    });
    std::vector<std::vector<std::pair<int, int>>> correspondences(g.models.size());
    for (std::size_t i = 0; i < nearest.size(); ++i) {
      const auto [row, d2] = nearest[i];
      if (row < 0 || !(d2 < max_d2)) continue;
      const std::size_t k = std::size_t(
          std::upper_bound(g.first_row.begin(), g.first_row.end(), row) - g.first_row.begin() - 1);
      correspondences[k].emplace_back(row - g.first_row[k], static_cast<int>(i));
    }
    const double ms_match = MsSince(t);
    out.match_ms += ms_match;

    // Each model groups and verifies its own matches, models side by side.
    parallel_for(g.models.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        const std::size_t m = g.models[k];
        if (!wanted(m)) continue;
        const ModelDescription& model = library.model(m);
        RecognitionResult& r = out.per_model[m];
        r.stats = described->stats;
        r.fovea = described->fovea;
        r.stats.stage_ms.emplace_back("match", ms_match);
        GroupAndVerify(model, scene, *described, correspondences[k],
                       RadiiForModel(given, model.scale()), parallel_for, &r);
        r.stats.stage_ms.emplace_back("total", MsSince(t_total));
        for (Detection& d : r.instances) d.model = static_cast<int>(m);
      }
    });
    for (std::size_t m : g.models)
      for (const auto& [stage, ms] : out.per_model[m].stats.stage_ms) {
        if (stage == "group") out.group_ms += ms;
        if (stage == "verify") out.verify_ms += ms;
      }
  }

  // One model per place: the best ranked (ArbitrationScore) or most voted instance first. A
  // single model's instances keep Recognize's order.
  std::vector<Detection> all;
  std::size_t found = 0;
  for (const RecognitionResult& r : out.per_model) {
    all.insert(all.end(), r.instances.begin(), r.instances.end());
    found += r.instances.empty() ? 0 : 1;
  }
  if (found <= 1) {
    out.instances = std::move(all);
    return out;
  }
  std::stable_sort(all.begin(), all.end(), [](const Detection& a, const Detection& b) {
    const float sa = ArbitrationScore(a), sb = ArbitrationScore(b);
    return sa != sb ? sa > sb : a.votes > b.votes;
  });
  for (Detection& d : all) {
    const float size = library.model(std::size_t(d.model)).scale().size_m;
    const bool taken = std::any_of(out.instances.begin(), out.instances.end(), [&](const auto& o) {
      return o.model != d.model &&
             ClaimSamePlace(d, size, o, library.model(std::size_t(o.model)).scale().size_m);
    });
    if (!taken) out.instances.push_back(std::move(d));
  }
  return out;
}

}  // namespace saccade
