#include "core/grouping.h"

#include "core/nearest_within.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace saccade {

namespace {

struct CellKey {
  int x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return (static_cast<std::size_t>(k.x) * 73856093u) ^
           (static_cast<std::size_t>(k.y) * 19349663u) ^
           (static_cast<std::size_t>(k.z) * 83492791u);
  }
};

// Rigid transform (no scale) taking `from` onto `to` in the least-squares sense. In double:
// GCC 12 sees a false out-of-bounds read in Eigen's float umeyama.
Eigen::Matrix4f FitRigid(const std::vector<Eigen::Vector3f>& from,
                         const std::vector<Eigen::Vector3f>& to) {
  Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    a.col(i) = from[i].cast<double>();
    b.col(i) = to[i].cast<double>();
  }
  return Eigen::umeyama(a, b, false).cast<float>();
}

// Local frames whose poses differ by less than this agree on the pose's rotation.
constexpr float kFramesAgreeRad = 30.0f * float(M_PI) / 180.0f;

// A symmetric model's matches of one place vote for one centroid but come from as many poses as
// it has turns. Keeps the `members` whose local frames agree with the frames of the member most
// others agree with, each given the turn that makes it agree, and returns their model points
// turned so (about the centroid): one pose fits them all. Without turns: every member, as it is.
std::vector<Eigen::Vector3f> AgreeingModelPoints(
    const Descriptors& model, const Cloud& model_cloud, const Eigen::Vector3f& model_centroid,
    const Descriptors& scene, const std::vector<std::pair<int, int>>& correspondences,
    const std::vector<Eigen::Matrix3f>& turns, std::vector<int>* members) {
  const auto point = [&](int c) {
    return Eigen::Vector3f(model_cloud[model.keypoint[correspondences[c].first]].getVector3fMap());
  };
  std::vector<Eigen::Vector3f> out;
  if (turns.size() <= 1) {
    for (int c : *members) out.push_back(point(c));
    return out;
  }
  const std::size_t n = members->size();
  std::vector<Eigen::Matrix3f> rotation(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [mi, si] = correspondences[(*members)[i]];
    rotation[i] = scene.lrf[si].transpose() * model.lrf[mi];
  }
  const float min_cos = std::cos(kFramesAgreeRad);
  // The turn of b's model that brings its rotation nearest a's, if near enough (-1: none).
  const auto turn_to = [&](std::size_t a, std::size_t b) {
    const Eigen::Matrix3f relative = rotation[a].transpose() * rotation[b];
    int best = -1;
    float best_cos = min_cos;
    for (std::size_t k = 0; k < turns.size(); ++k) {
      const float c = ((relative * turns[k].transpose()).trace() - 1) / 2;
      if (c >= best_cos) best_cos = c, best = int(k);
    }
    return best;
  };
  std::size_t seed = 0;
  int seed_count = -1;
  for (std::size_t a = 0; a < n; ++a) {
    int count = 0;
    for (std::size_t b = 0; b < n; ++b) count += turn_to(a, b) >= 0;
    if (count > seed_count) seed_count = count, seed = a;
  }
  std::vector<int> kept;
  for (std::size_t b = 0; b < n; ++b) {
    const int k = turn_to(seed, b);
    if (k < 0) continue;
    kept.push_back((*members)[b]);
    out.push_back(model_centroid + turns[std::size_t(k)] * (point((*members)[b]) - model_centroid));
  }
  members->swap(kept);
  return out;
}

// Points bucketed in cubes, to list those that may lie within a distance of a place without
// looking at the others.
class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3f>& points, float cell) : cell_(cell) {
    for (std::size_t i = 0; i < points.size(); ++i)
      if (points[i].allFinite()) cells_[KeyOf(points[i])].push_back(int(i));
  }
  /// Appends to `out` the points of the cubes that come within `radius` of `at`: every point
  /// within `radius`, and some farther, in no particular order.
  void Around(const Eigen::Vector3f& at, float radius, std::vector<int>* out) const {
    if (!at.allFinite()) return;
    const CellKey c = KeyOf(at);
    const int reach = int(std::ceil(radius / cell_));
    const Eigen::Vector3f in_cell = at / cell_ - Eigen::Vector3f(c.x, c.y, c.z);  // in [0, 1)
    const float r2 = (radius / cell_) * (radius / cell_);
    // How far, in cells, `at` lies from the cube d cells away along one axis.
    const auto gap = [](float x, int d) { return d > 0 ? d - x : d < 0 ? x - d - 1 : 0.0f; };
    for (int dz = -reach; dz <= reach; ++dz)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const float gx = gap(in_cell.x(), dx), gy = gap(in_cell.y(), dy),
                      gz = gap(in_cell.z(), dz);
          if (gx * gx + gy * gy + gz * gz > r2) continue;
          const auto it = cells_.find({c.x + dx, c.y + dy, c.z + dz});
          if (it != cells_.end()) out->insert(out->end(), it->second.begin(), it->second.end());
        }
  }

 private:
  CellKey KeyOf(const Eigen::Vector3f& p) const {
    const Eigen::Vector3f s = (p / cell_).array().floor();
    return {int(s.x()), int(s.y()), int(s.z())};
  }
  float cell_;
  std::unordered_map<CellKey, std::vector<int>, CellHash> cells_;
};

}  // namespace

std::vector<Detection> HoughGroup(const Descriptors& model, const Cloud& model_cloud,
                                  const Eigen::Vector3f& model_centroid, const Descriptors& scene,
                                  const Cloud& scene_cloud,
                                  const std::vector<std::pair<int, int>>& correspondences,
                                  const RecognitionOptions& options,
                                  const std::vector<Eigen::Matrix3f>& turns) {
  const float bin = options.hough_bin_m;
  // Each correspondence votes for where the model centroid lies in the scene: the centroid's
  // offset in the model keypoint's local frame, carried into the scene keypoint's frame.
  std::vector<Eigen::Vector3f> votes;
  std::vector<int> voter;
  for (std::size_t c = 0; c < correspondences.size(); ++c) {
    const auto [mi, si] = correspondences[c];
    const Eigen::Vector3f pm = model_cloud[model.keypoint[mi]].getVector3fMap();
    const Eigen::Vector3f ps = scene_cloud[scene.keypoint[si]].getVector3fMap();
    const Eigen::Vector3f local = model.lrf[mi] * (model_centroid - pm);
    const Eigen::Vector3f vote = ps + scene.lrf[si].transpose() * local;
    if (!vote.allFinite()) continue;
    votes.push_back(vote);
    voter.push_back(static_cast<int>(c));
  }
  // Trilinear interpolation spreads each vote over the 8 cells around it.
  std::unordered_map<CellKey, float, CellHash> acc;
  for (const auto& v : votes) {
    const Eigen::Vector3f s = v / bin - Eigen::Vector3f::Constant(0.5f);
    const Eigen::Vector3f f = s.array().floor();
    const Eigen::Vector3f t = s - f;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const float w =
              (dx ? t.x() : 1 - t.x()) * (dy ? t.y() : 1 - t.y()) * (dz ? t.z() : 1 - t.z());
          acc[{static_cast<int>(f.x()) + dx, static_cast<int>(f.y()) + dy,
               static_cast<int>(f.z()) + dz}] += w;
        }
  }
  // Peaks: cells at or over the threshold that no neighbour beats (ties go to the lower key).
  std::vector<std::pair<CellKey, float>> peaks;
  for (const auto& [key, value] : acc) {
    if (value < options.hough_threshold) continue;
    bool is_max = true;
    for (int dz = -1; dz <= 1 && is_max; ++dz)
      for (int dy = -1; dy <= 1 && is_max; ++dy)
        for (int dx = -1; dx <= 1 && is_max; ++dx) {
          if (!dx && !dy && !dz) continue;
          const CellKey n{key.x + dx, key.y + dy, key.z + dz};
          auto it = acc.find(n);
          if (it == acc.end()) continue;
          if (it->second > value ||
              (it->second == value && std::tie(n.x, n.y, n.z) < std::tie(key.x, key.y, key.z)))
            is_max = false;
        }
    if (is_max) peaks.emplace_back(key, value);
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second
                                : std::tie(a.first.x, a.first.y, a.first.z) <
                                      std::tie(b.first.x, b.first.y, b.first.z);
  });

  std::vector<Detection> out;
  const float thr2 = options.pose_inlier_threshold_m * options.pose_inlier_threshold_m;
  for (const auto& [key, value] : peaks) {
    // The peak's correspondences: votes that reached its cell through the interpolation.
    const Eigen::Vector3f centre =
        (Eigen::Vector3f(key.x, key.y, key.z) + Eigen::Vector3f::Constant(0.5f)) * bin;
    std::vector<int> members;
    for (std::size_t v = 0; v < votes.size(); ++v)
      if (((votes[v] - centre).cwiseAbs().array() < bin).all()) members.push_back(voter[v]);
    if (static_cast<int>(members.size()) < 3) continue;
    std::vector<Eigen::Vector3f> from = AgreeingModelPoints(
        model, model_cloud, model_centroid, scene, correspondences, turns, &members);
    std::vector<Eigen::Vector3f> to;
    for (int c : members)
      to.push_back(scene_cloud[scene.keypoint[correspondences[c].second]].getVector3fMap());
    if (static_cast<int>(members.size()) < 3) continue;
    Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();
    // Fit, drop correspondences the fit does not explain, fit again (at most a few rounds).
    for (int round = 0; round < 4; ++round) {
      pose = FitRigid(from, to);
      std::vector<int> inliers;
      std::vector<Eigen::Vector3f> from_in, to_in;
      for (std::size_t i = 0; i < members.size(); ++i) {
        const Eigen::Vector3f mapped =
            pose.topLeftCorner<3, 3>() * from[i] + pose.topRightCorner<3, 1>();
        if ((mapped - to[i]).squaredNorm() > thr2) continue;
        inliers.push_back(members[i]);
        from_in.push_back(from[i]);
        to_in.push_back(to[i]);
      }
      const bool done = inliers.size() == members.size() || inliers.size() < 3;
      members.swap(inliers);
      from.swap(from_in);
      to.swap(to_in);
      if (done) break;
    }
    if (static_cast<int>(members.size()) < options.hough_threshold) continue;
    if (!pose.allFinite()) continue;
    const Eigen::Matrix3f R = pose.topLeftCorner<3, 3>();
    if (std::abs(R.determinant() - 1.0f) > 1e-3f) continue;  // only proper rotations leave
    Detection d;
    d.model_to_scene = pose;
    d.votes = static_cast<int>(members.size());
    d.centroid_m = R * model_centroid + pose.topRightCorner<3, 1>();
    for (int c : members)
      d.correspondences.emplace_back(model.keypoint[correspondences[c].first],
                                     scene.keypoint[correspondences[c].second]);
    // Two peaks of one object (a split vote) are one instance: keep the stronger.
    bool duplicate = false;
    for (const Detection& kept : out)
      if ((kept.centroid_m - d.centroid_m).norm() < 2.0f * bin) duplicate = true;
    if (!duplicate) out.push_back(std::move(d));
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Detection& a, const Detection& b) { return a.votes > b.votes; });
  return out;
}

std::vector<Detection> ConsensusGroup(const Descriptors& model, const Cloud& model_cloud,
                                      const Eigen::Vector3f& model_centroid,
                                      const Descriptors& scene, const Cloud& scene_cloud,
                                      const std::vector<std::pair<int, int>>& correspondences,
                                      const RecognitionOptions& options,
                                      const std::vector<Eigen::Matrix3f>& turns) {
  const std::size_t n = correspondences.size();
  std::vector<Eigen::Vector3f> from(n), to(n);
  std::vector<Eigen::Matrix4f> pose(n, Eigen::Matrix4f::Identity());
  for (std::size_t c = 0; c < n; ++c) {
    const auto [mi, si] = correspondences[c];
    from[c] = model_cloud[model.keypoint[mi]].getVector3fMap();
    to[c] = scene_cloud[scene.keypoint[si]].getVector3fMap();
    // The two local frames give the whole pose: rotation R = L_s^T L_m, then the keypoints meet.
    const Eigen::Matrix3f R = scene.lrf[si].transpose() * model.lrf[mi];
    pose[c].topLeftCorner<3, 3>() = R;
    pose[c].topRightCorner<3, 1>() = to[c] - R * from[c];
  }
  // A symmetric model's point c is also each of its turns about the centroid: a match agrees
  // with a pose through whichever turn the pose takes nearest its scene point.
  // (The identity is `from` itself, not a copy: most models have no other turn.)
  std::vector<std::vector<Eigen::Vector3f>> others;
  for (std::size_t k = 1; k < turns.size(); ++k) {
    others.emplace_back(n);
    for (std::size_t c = 0; c < n; ++c)
      others.back()[c] = model_centroid + turns[k] * (from[c] - model_centroid);
  }
  std::vector<const std::vector<Eigen::Vector3f>*> turned{&from};
  for (const auto& points : others) turned.push_back(&points);
  const float thr2 = options.pose_inlier_threshold_m * options.pose_inlier_threshold_m;
  // A match agrees with a pose only if its scene point lies within its model point's distance
  // from the centroid (turns keep it), plus the threshold, of where the pose puts the centroid:
  // only scene points that near are tried (a millimetre more for rounding). Models are rigid,
  // so this gives the answer trying every match would, in a fraction of the time.
  float reach = 0;
  for (const Eigen::Vector3f& f : from)
    if (f.allFinite()) reach = std::max(reach, (f - model_centroid).norm());
  reach += options.pose_inlier_threshold_m + 1e-3f;
  const PointGrid near(to, reach / 2);
  std::vector<int> tried;
  // The matches that agree with `p`, each as (match, its model point as the pose takes it), in
  // the order of the matches.
  const auto agreeing = [&](const Eigen::Matrix4f& p) {
    std::vector<std::pair<int, Eigen::Vector3f>> members;
    const Eigen::Matrix3f R = p.topLeftCorner<3, 3>();
    const Eigen::Vector3f t = p.topRightCorner<3, 1>();
    tried.clear();
    near.Around(R * model_centroid + t, reach, &tried);
    for (const int c : tried) {
      float best = thr2;
      const Eigen::Vector3f* point = nullptr;
      for (const std::vector<Eigen::Vector3f>* model_points : turned) {
        const float d2 = (R * (*model_points)[c] + t - to[c]).squaredNorm();
        if (d2 <= best) best = d2, point = &(*model_points)[c];
      }
      if (point) members.emplace_back(c, *point);
    }
    std::sort(members.begin(), members.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    return members;
  };
  std::vector<int> support(n, 0);
  for (std::size_t c = 0; c < n; ++c)
    if (pose[c].allFinite()) support[c] = int(agreeing(pose[c]).size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return support[a] > support[b]; });
  std::vector<std::uint8_t> used(n, 0);
  std::vector<Detection> out;
  for (int seed : order) {
    if (support[seed] < options.consensus_min_votes ||
        int(out.size()) >= options.consensus_max_hypotheses)
      break;
    if (used[seed]) continue;
    // Refit on the seed's agreeing matches, re-gather, twice: the seed's own frames are noisy.
    Eigen::Matrix4f p = pose[seed];
    auto members = agreeing(p);
    for (int round = 0; round < 2 && int(members.size()) >= 3; ++round) {
      std::vector<Eigen::Vector3f> a, b;
      for (const auto& [c, point] : members) a.push_back(point), b.push_back(to[c]);
      const Eigen::Matrix4f refit = FitRigid(a, b);
      if (!refit.allFinite()) break;
      auto again = agreeing(refit);
      if (again.size() < members.size()) break;
      p = refit;
      members.swap(again);
    }
    for (const auto& member : members) used[member.first] = 1;
    used[seed] = 1;
    if (int(members.size()) < options.consensus_min_votes) continue;
    const Eigen::Matrix3f R = p.topLeftCorner<3, 3>();
    if (std::abs(R.determinant() - 1.0f) > 1e-3f) continue;
    Detection d;
    d.model_to_scene = p;
    d.votes = int(members.size());
    d.centroid_m = R * model_centroid + p.topRightCorner<3, 1>();
    for (const auto& member : members)
      d.correspondences.emplace_back(model.keypoint[correspondences[member.first].first],
                                     scene.keypoint[correspondences[member.first].second]);
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<Detection> MergeHypotheses(std::vector<Detection> a, std::vector<Detection> b,
                                       float min_separation_m) {
  for (Detection& d : b) {
    const bool duplicate = std::any_of(a.begin(), a.end(), [&](const Detection& k) {
      return (k.centroid_m - d.centroid_m).norm() < min_separation_m;
    });
    if (!duplicate) a.push_back(std::move(d));
  }
  std::stable_sort(a.begin(), a.end(),
                   [](const Detection& x, const Detection& y) { return x.votes > y.votes; });
  return a;
}

}  // namespace saccade
