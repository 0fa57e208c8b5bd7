#include "core/symmetry.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <unordered_map>

namespace saccade {

namespace {

constexpr float kSameTurnRad = 10.0f * float(M_PI) / 180.0f;

// The surface's points relative to the centre, hashed in cubes of `cell_m`: the nearest point
// within cell_m of a place is in one of the 27 cubes around it.
class PointHash {
 public:
  PointHash(std::vector<Eigen::Vector3f> points, float cell_m)
      : points_(std::move(points)), cell_(cell_m) {
    for (std::size_t i = 0; i < points_.size(); ++i) cells_[Key(points_[i])].push_back(int(i));
  }
  // The nearest point within `radius_m` (<= the cell), or nullptr.
  const Eigen::Vector3f* Nearest(const Eigen::Vector3f& q, float radius_m) const {
    const Eigen::Vector3i k = Cell(q);
    const Eigen::Vector3f* best = nullptr;
    float best_d2 = radius_m * radius_m;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(Pack(k + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (int i : it->second) {
            const float d2 = (points_[std::size_t(i)] - q).squaredNorm();
            if (d2 <= best_d2) best_d2 = d2, best = &points_[std::size_t(i)];
          }
        }
    return best;
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3f& p) const {
    return (p / cell_).array().floor().cast<int>();
  }
  static std::uint64_t Pack(const Eigen::Vector3i& k) {
    const auto part = [](int v) { return std::uint64_t(std::uint32_t(v + (1 << 20))) & 0x1fffff; };
    return part(k.x()) | part(k.y()) << 21 | part(k.z()) << 42;
  }
  std::uint64_t Key(const Eigen::Vector3f& p) const { return Pack(Cell(p)); }

  std::vector<Eigen::Vector3f> points_;
  float cell_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// A quaternion's bin, each component in -10..10.
std::uint32_t Pack4(const Eigen::Vector4i& b) {
  std::uint32_t key = 0;
  for (int i = 0; i < 4; ++i) key = key * 32 + std::uint32_t(b[i] + 10);
  return key;
}

// Aligns `turn` (about the origin) so that the turned samples meet the surface, then scores it:
// the share of samples within `tolerance_m` of a surface point.
float RefineAndScore(const std::vector<Eigen::Vector3f>& samples, const PointHash& surface,
                     float tolerance_m, Eigen::Matrix3f* turn) {
  constexpr int kRounds = 8;  // pairing within 3 tolerances at first, within one at the end
  for (int round = 0; round < kRounds; ++round) {
    const float reach = tolerance_m * (3 - 2 * float(round) / float(kRounds - 1));
    Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
    int pairs = 0;
    for (const Eigen::Vector3f& s : samples) {
      const Eigen::Vector3f q = *turn * s;
      if (const Eigen::Vector3f* p = surface.Nearest(q, reach)) {
        cross += p->cast<double>() * s.cast<double>().transpose();
        ++pairs;
      }
    }
    if (pairs < 3) return 0;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2, 2) = -1;
    *turn = (svd.matrixU() * d * svd.matrixV().transpose()).cast<float>();
  }
  int near = 0;
  for (const Eigen::Vector3f& s : samples)
    if (surface.Nearest(*turn * s, tolerance_m)) ++near;
  return float(near) / float(samples.size());
}

// Turns about `centre` proposed by keypoints alike (near descriptors, as far from the centre,
// apart): the turn their local frames give, binned by its quaternion (w >= 0, steps of 0.1, about
// 11 degrees); each bin with how many pairs proposed it, the most first.
std::vector<std::pair<Eigen::Matrix3f, int>> ProposeTurns(const Cloud& surface,
                                                          const Eigen::Vector3f& centre,
                                                          const Descriptors& descriptors,
                                                          const SymmetryOptions& options) {
  const std::size_t step = std::max<std::size_t>(1, descriptors.size() / 400);
  std::vector<std::size_t> picked;
  for (std::size_t i = 0; i < descriptors.size(); i += step) picked.push_back(i);
  std::unordered_map<std::uint32_t, std::pair<Eigen::Matrix3f, int>> bins;
  for (std::size_t a : picked) {
    const Eigen::Vector3f ra =
        surface[std::size_t(descriptors.keypoint[a])].getVector3fMap() - centre;
    for (std::size_t b : picked) {
      if (a == b) continue;
      const Eigen::Vector3f rb =
          surface[std::size_t(descriptors.keypoint[b])].getVector3fMap() - centre;
      if (std::abs(ra.norm() - rb.norm()) > 2 * options.tolerance_m ||
          (ra - rb).norm() < 2 * options.tolerance_m)
        continue;
      float d2 = 0;
      for (int k = 0; k < kShotLength && d2 < options.max_sqr_distance; ++k) {
        const float d = descriptors.Row(a)[k] - descriptors.Row(b)[k];
        d2 += d * d;
      }
      if (d2 >= options.max_sqr_distance) continue;
      // Frames' rows are axes: the turn taking a's neighbourhood onto b's is L_b^T L_a.
      const Eigen::Matrix3f turn = descriptors.lrf[b].transpose() * descriptors.lrf[a];
      if (!turn.allFinite() || (turn * ra - rb).norm() > 0.25f * ra.norm() + options.tolerance_m)
        continue;
      Eigen::Quaternionf q(turn);
      if (q.w() < 0) q.coeffs() = -q.coeffs();
      const Eigen::Vector4i bin = (q.coeffs() * 10).array().round().cast<int>();
      auto& c = bins[Pack4(bin)];
      if (c.second++ == 0) c.first = turn;
    }
  }
  std::vector<std::pair<Eigen::Matrix3f, int>> candidates;
  for (const auto& [key, c] : bins) candidates.push_back(c);
  std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) {
    return x.second != y.second ? x.second > y.second
                                : std::make_tuple(x.first(0, 0), x.first(0, 1), x.first(1, 0)) <
                                      std::make_tuple(y.first(0, 0), y.first(0, 1), y.first(1, 0));
  });
  return candidates;
}

}  // namespace

float RotationAngle(const Eigen::Matrix3f& r) {
  return std::acos(std::clamp((r.trace() - 1.0f) / 2.0f, -1.0f, 1.0f));
}

std::vector<Eigen::Matrix3f> FindSymmetries(const Cloud& surface, const Eigen::Vector3f& centre,
                                            const Descriptors& descriptors,
                                            const SymmetryOptions& options) {
  std::vector<Eigen::Matrix3f> out{Eigen::Matrix3f::Identity()};
  std::vector<Eigen::Vector3f> points;
  for (const PointT& p : surface.points)
    if (FinitePoint(p)) points.push_back(p.getVector3fMap() - centre);
  if (points.size() < 3 || descriptors.size() < 2) return out;
  std::vector<Eigen::Vector3f> samples;
  const std::size_t sample_step = std::max<std::size_t>(1, points.size() / 300);
  for (std::size_t i = 0; i < points.size(); i += sample_step) samples.push_back(points[i]);
  const PointHash hash(std::move(points), 3 * options.tolerance_m);

  std::vector<std::pair<Eigen::Matrix3f, int>> candidates =
      ProposeTurns(surface, centre, descriptors, options);
  if (candidates.size() > 200) candidates.resize(200);
  for (auto& [turn, count] : candidates) {
    if (int(out.size()) >= options.max_turns) break;
    if (RefineAndScore(samples, hash, options.tolerance_m, &turn) < options.min_share) continue;
    const bool known = std::any_of(out.begin(), out.end(), [&](const Eigen::Matrix3f& kept) {
      return RotationAngle(kept.transpose() * turn) < kSameTurnRad;
    });
    if (!known) out.push_back(turn);
  }
  return out;
}

}  // namespace saccade
