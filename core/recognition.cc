#include "core/recognition.h"

#include "core/candidates.h"
#include "core/check.h"
#include "core/fail.h"
#include "core/nearest_within.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <type_traits>
#include <unordered_map>

namespace saccade {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The search budget: `budget` of the keypoints, in order of distance from the fovea, the
// query's phase choosing the window (windows start every budget / 2 keypoints).
std::vector<int> BudgetedWindow(const Cloud& scene, const std::vector<int>& keypoints,
                                const SceneQuery& query, int budget, RecognitionStats* stats) {
  std::vector<std::pair<float, int>> by_distance;
  by_distance.reserve(keypoints.size());
  for (int i : keypoints)
    by_distance.emplace_back((scene[std::size_t(i)].getVector3fMap() - query.fovea_m).squaredNorm(),
                             i);
  std::sort(by_distance.begin(), by_distance.end());
  const std::size_t n = by_distance.size(), size = std::size_t(budget),
                    step = std::max<std::size_t>(1, size / 2);
  const std::size_t windows = (n - size + step - 1) / step + 1;
  // Every other frame looks again where the object was lost (window 0: what reappears from
  // behind an occluder is found there); the frames between walk outward through the others.
  const std::size_t phase = std::size_t(std::max(0, query.search_phase));
  const std::size_t w = phase % 2 == 0 || windows == 1 ? 0 : 1 + (phase / 2) % (windows - 1);
  const std::size_t first = std::min(w * step, n - size);
  std::vector<std::uint8_t> in_window(scene.size(), 0);
  for (std::size_t k = first; k < first + size; ++k)
    in_window[std::size_t(by_distance[k].second)] = 1;
  std::vector<int> kept;  // in the keypoints' own order, as without a budget
  kept.reserve(size);
  for (int i : keypoints)
    if (in_window[std::size_t(i)]) kept.push_back(i);
  stats->budgeted_out = n - size;
  stats->search_windows = static_cast<int>(windows);
  return kept;
}

// A model of several captured views is verified as one surface, its views placed where their
// alignment put them; a view misplaced by that alignment makes a right pose look wrong (points
// in front of the scene, a share of the surface missing). A hypothesis the whole model failed
// (not one a better instance took) is verified again against the view most of its votes came
// from, as that view alone would be as a one-view model, and kept where nothing kept is and it is
// confident enough (VerificationOptions::min_view_confidence).
void VerifyByViews(const ModelDescription& model, const Cloud& scene,
                   const SceneDescription& described, const RecognitionOptions& options,
                   const ParallelFor& parallel_for, const std::vector<std::size_t>& verified,
                   RecognitionResult* result) {
  const auto& views = model.view_verification();
  if (views.empty() || options.verify.min_view_confidence >= 1) return;
  VerificationOptions alone = options.verify;
  alone.min_confidence = std::max(alone.min_confidence, alone.min_view_confidence);
  std::vector<std::vector<std::size_t>> by_view(views.size());  // into result->hypotheses
  for (std::size_t h : verified) {
    if (!FailedACheck(result->verdicts[h])) continue;
    std::vector<int> votes(views.size(), 0);
    for (const auto& [m, s] : result->hypotheses[h].correspondences) ++votes[model.ViewOf(m)];
    by_view[std::max_element(votes.begin(), votes.end()) - votes.begin()].push_back(h);
  }
  std::vector<std::pair<Detection, std::size_t>> kept;  // with its hypothesis
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (by_view[v].empty()) continue;
    std::vector<Detection> again;
    for (std::size_t h : by_view[v]) again.push_back(result->hypotheses[h]);
    for (Detection& d : VerifyInstances(views[v], model.centroid(), scene, described.intrinsics,
                                        std::move(again), alone, parallel_for)) {
      const auto h = std::find_if(by_view[v].begin(), by_view[v].end(), [&](std::size_t i) {
        return result->hypotheses[i].correspondences == d.correspondences;
      });
      if (h != by_view[v].end()) kept.emplace_back(std::move(d), *h);
    }
  }
  std::stable_sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) {
    return a.first.confidence > b.first.confidence;
  });
  // Two instances cannot be one object: nearer than the model's half diagonal, the one kept
  // first stays (the whole model's before any view's).
  const float apart = model.verification().radius_m;
  for (auto& [d, h] : kept) {
    const bool near = std::any_of(
        result->instances.begin(), result->instances.end(),
        [&](const Detection& o) { return (o.centroid_m - d.centroid_m).norm() < apart; });
    result->verdicts[h] = near ? Verdict::kTakenByBetter : Verdict::kKept;
    if (!near) result->instances.push_back(std::move(d));
  }
}

}  // namespace

std::size_t RecognitionStats::TotalPoints() const {
  return std::accumulate(level_points.begin(), level_points.end(), std::size_t{0});
}
std::size_t RecognitionStats::TotalKeypoints() const {
  return std::accumulate(level_keypoints.begin(), level_keypoints.end(), std::size_t{0});
}

std::optional<SceneDescription> DescribeScene(const Cloud& scene, const SceneQuery& query,
                                              const RecognitionOptions& options,
                                              const ParallelFor& parallel_for, std::string* error,
                                              SceneNormals* shared_normals) {
  SceneDescription out;
  auto& stats = out.stats;
  auto t = Clock::now();

  // 1. Which points to keep, per level, and with which keypoint radius. Only the levels fine
  // enough to describe are computed: the periphery's points would never be used.
  std::optional<CameraIntrinsics> intrinsics = query.intrinsics;
  if (!intrinsics && scene.height > 1) intrinsics = EstimateIntrinsics(scene);
  const bool organized = intrinsics.has_value() && scene.height > 1;
  if (organized) out.intrinsics = intrinsics;
  std::vector<std::vector<int>> level_points;  // indices into `scene`
  std::vector<float> level_radius;
  if (query.foveated) {
    const auto bounds = BoundingBox(scene);
    if (!bounds) {
      Fail(error, "scene has no finite point");
      return std::nullopt;
    }
    const FoveaGeometry geometry = ComputeFoveaGeometry(query.fovea, *bounds, query.fovea_m);
    int first = query.fovea.finest_level;
    while (first > 0 && LevelDensity(query.fovea, first - 1) <= options.max_described_density_m)
      --first;
    level_points =
        FoveateIndices(scene, query.fovea, geometry, first, organized ? &*intrinsics : nullptr);
    for (int k = 0; k <= query.fovea.finest_level; ++k)
      level_radius.push_back(LevelKeypointRadius(query.fovea, k));
    out.fovea = geometry;
  } else {
    level_points.emplace_back();
    for (int i = 0, n = static_cast<int>(scene.size()); i < n; ++i)
      if (FinitePoint(scene[i])) level_points.back().push_back(i);
    if (level_points.back().empty()) {
      Fail(error, "scene has no finite point");
      return std::nullopt;
    }
    level_radius.push_back(options.scene_keypoint_radius_m);
  }
  std::vector<std::uint8_t> mask(scene.size(), 0);
  for (const auto& level : level_points)
    for (int i : level) mask[i] = 1;
  for (const auto& level : level_points) stats.level_points.push_back(level.size());
  stats.stage_ms.emplace_back("foveate", MsSince(t));

  // 2. Keypoints per level, each with its own radius.
  t = Clock::now();
  std::vector<int> keypoints;
  for (std::size_t k = 0; k < level_points.size(); ++k) {
    const auto kp = VoxelRepresentatives(scene, level_points[k], level_radius[k]);
    stats.level_keypoints.push_back(kp.size());
    keypoints.insert(keypoints.end(), kp.begin(), kp.end());
  }
  if (options.table_keypoint_distance_m > 0 && organized) {
    if (const auto plane = TablePlane(scene, CandidateOptions{})) {
      const std::size_t before = keypoints.size();
      keypoints.erase(std::remove_if(keypoints.begin(), keypoints.end(),
                                     [&](int i) {
                                       const Eigen::Vector3f p =
                                           scene[std::size_t(i)].getVector3fMap();
                                       return std::abs(plane->head<3>().dot(p) + (*plane)[3]) <=
                                              options.table_keypoint_distance_m;
                                     }),
                      keypoints.end());
      stats.table_keypoints = before - keypoints.size();
    }
  }
  if (options.max_scene_keypoints > 0 &&
      keypoints.size() > static_cast<std::size_t>(options.max_scene_keypoints))
    keypoints = BudgetedWindow(scene, keypoints, query, options.max_scene_keypoints, &stats);
  stats.stage_ms.emplace_back("keypoints", MsSince(t));

  // 3. SHOT with its local frame, on the kept points as the search surface, and the normals
  // they read, from the full-resolution geometry. With sampled supports (a bounded number of
  // points each) the supports are found first and normals computed only where they read them:
  // a fraction of the kept points. Unsampled supports read nearly every kept point, and held
  // in memory they would run to hundreds of megabytes on a whole frame: there every kept
  // point gets its normal and each support is found as it is described.
  const auto search =
      organized ? MakeOrganizedSearch(scene, *intrinsics, mask, options.max_support_half_window_px)
                : MakeKdTreeSearch(scene, mask);
  DescribeOptions describe;
  describe.shot_radius_m = options.scene_shot_radius_m;
  describe.lrf_radius_m = options.scene_lrf_radius_m;
  SceneNormals own_normals;
  SceneNormals& scene_normals = shared_normals ? *shared_normals : own_normals;
  const auto normals_on = [&](const std::vector<std::uint8_t>& where) -> const Normals& {
    return scene_normals.On(scene, organized ? &*intrinsics : nullptr,
                            options.scene_normal_neighbors, where, parallel_for);
  };
  if (organized && options.max_support_half_window_px > 0) {
    t = Clock::now();
    const Supports supports = FindSupports(scene, keypoints, *search, describe, parallel_for);
    const double ms_supports = MsSince(t);
    t = Clock::now();
    const Normals& normals = normals_on(SupportMask(supports, scene.size()));
    stats.stage_ms.emplace_back("normals", MsSince(t));
    t = Clock::now();
    out.descriptors =
        DescribeKeypoints(scene, normals, keypoints, supports, describe, parallel_for);
    stats.stage_ms.emplace_back("describe", ms_supports + MsSince(t));
  } else {
    t = Clock::now();
    const Normals& normals = normals_on(mask);
    stats.stage_ms.emplace_back("normals", MsSince(t));
    t = Clock::now();
    out.descriptors = DescribeKeypoints(scene, normals, keypoints, *search, describe, parallel_for);
    stats.stage_ms.emplace_back("describe", MsSince(t));
  }
  stats.described = out.descriptors.size();
  return out;
}

void GroupAndVerify(const ModelDescription& model, const Cloud& scene,
                    const SceneDescription& described,
                    const std::vector<std::pair<int, int>>& correspondences,
                    const RecognitionOptions& options, const ParallelFor& parallel_for,
                    RecognitionResult* result) {
  auto& stats = result->stats;
  const Descriptors& scene_desc = described.descriptors;
  stats.correspondences = correspondences.size();
  for (const auto& [m, d] : correspondences)
    result->correspondences.emplace_back(model.descriptors().keypoint[m], scene_desc.keypoint[d]);

  // 5. Hough voting and pose per instance.
  auto t = Clock::now();
  result->instances = HoughGroup(model.descriptors(), model.cloud(), model.centroid(), scene_desc,
                                 scene, correspondences, options, model.symmetries());
  if (options.consensus_grouping)
    result->instances = MergeHypotheses(
        std::move(result->instances),
        ConsensusGroup(model.descriptors(), model.cloud(), model.centroid(), scene_desc, scene,
                       correspondences, options, model.symmetries()),
        2.0f * options.hough_bin_m);
  stats.hypotheses = result->instances.size();
  result->hypotheses = result->instances;
  stats.stage_ms.emplace_back("group", MsSince(t));

  // 6. Keep the hypotheses whose votes stand out of the model's matches and the scene
  // confirms, refined.
  t = Clock::now();
  const double min_votes =
      options.min_vote_significance * std::sqrt(double(correspondences.size()));
  std::vector<Detection> significant;
  std::vector<std::size_t> significant_index;  // into result->hypotheses
  for (std::size_t h = 0; h < result->instances.size(); ++h)
    if (result->instances[h].votes >= min_votes) {
      significant.push_back(std::move(result->instances[h]));
      significant_index.push_back(h);
    }
  result->instances = std::move(significant);
  if (options.verify.enabled) {
    std::vector<Verdict> verdicts;
    result->instances =
        VerifyInstances(model.verification(), model.centroid(), scene, described.intrinsics,
                        std::move(result->instances), options.verify, parallel_for, &verdicts);
    result->verdicts.assign(result->hypotheses.size(), Verdict::kFewVotes);
    for (std::size_t i = 0; i < verdicts.size(); ++i)
      result->verdicts[significant_index[i]] = verdicts[i];
    VerifyByViews(model, scene, described, options, parallel_for, significant_index, result);
  }
  stats.stage_ms.emplace_back("verify", MsSince(t));
}

RecognitionResult Recognize(const ModelDescription& model, const Cloud& scene,
                            const SceneQuery& query, const RecognitionOptions& given,
                            const ParallelFor& parallel_for, std::string* error) {
  SACCADE_CHECK_VALID(given);
  SACCADE_CHECK_VALID(query.fovea);
  const RecognitionOptions options = RadiiForModel(given, model.scale());
  RecognitionResult result;
  const auto t_total = Clock::now();
  std::optional<SceneDescription> described =
      DescribeScene(scene, query, options, parallel_for, error);
  if (!described) return result;
  result.stats = std::move(described->stats);
  result.fovea = described->fovea;

  // 4. Nearest model descriptor of each scene descriptor.
  const auto t = Clock::now();
  const Descriptors& scene_desc = described->descriptors;
  std::vector<std::pair<int, float>> nearest(scene_desc.size());
  parallel_for(scene_desc.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      nearest[i] = model.Nearest(scene_desc.Row(i), options.max_descriptor_sqr_distance);
  });
  std::vector<std::pair<int, int>> correspondences;
  for (std::size_t i = 0; i < nearest.size(); ++i)
    if (nearest[i].first >= 0 && nearest[i].second < options.max_descriptor_sqr_distance)
      correspondences.emplace_back(nearest[i].first, static_cast<int>(i));
  result.stats.stage_ms.emplace_back("match", MsSince(t));

  GroupAndVerify(model, scene, *described, correspondences, options, parallel_for, &result);
  result.stats.stage_ms.emplace_back("total", MsSince(t_total));
  return result;
}

PoseError ComparePoses(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                       const Eigen::Vector3f& model_point) {
  const Eigen::Affine3d e(estimate.cast<double>()), g(truth.cast<double>());
  PoseError err;
  err.translation_m = (e * model_point.cast<double>() - g * model_point.cast<double>()).norm();
  const Eigen::Matrix3d dR = e.linear().transpose() * g.linear();
  const double c = std::clamp((dR.trace() - 1.0) / 2.0, -1.0, 1.0);
  err.rotation_deg = std::acos(c) * 180.0 / EIGEN_PI;
  return err;
}

}  // namespace saccade
