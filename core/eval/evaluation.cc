#include "core/eval/evaluation.h"

#include "core/fail.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <tuple>

namespace saccade {

SceneScore ScoreScene(const std::vector<Eigen::Vector3f>& detected_m,
                      const Eigen::Vector3f& truth_m, float threshold_m) {
  SceneScore score;
  int within = 0;
  for (const Eigen::Vector3f& d : detected_m) {
    const float distance = (d - truth_m).norm();
    if (score.nearest_m < 0 || distance < score.nearest_m) score.nearest_m = distance;
    if (distance <= threshold_m) ++within;
  }
  score.true_positives = within > 0 ? 1 : 0;
  score.false_positives = static_cast<int>(detected_m.size()) - within;
  return score;
}

Interval WilsonInterval(int successes, int n, double z) {
  if (n <= 0) return {};
  const double p = double(successes) / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double SymmetricPoseDistance(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                             const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) return 0;
  std::vector<Eigen::Vector3f> placed;
  placed.reserve(points.size());
  for (const Eigen::Vector3f& p : points) placed.push_back((truth * p.homogeneous()).head<3>());
  double sum = 0;
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3f q = (estimate * p.homogeneous()).head<3>();
    float best = std::numeric_limits<float>::infinity();
    for (const Eigen::Vector3f& t : placed) best = std::min(best, (q - t).squaredNorm());
    sum += std::sqrt(double(best));
  }
  return sum / double(points.size());
}

const char* CaseStageName(CaseStage s) {
  switch (s) {
    case CaseStage::kFound:
      return "found";
    case CaseStage::kNoCorrectCorrespondence:
      return "no_correct_correspondence";
    case CaseStage::kNoHypothesis:
      return "no_hypothesis_near_truth";
    case CaseStage::kNotVerified:
      return "true_hypothesis_not_verified";
    case CaseStage::kRejected:
      return "true_hypothesis_rejected";
    case CaseStage::kOutranked:
      return "outranked_by_false";
  }
  return "?";
}

CaseStage DiagnoseCase(const CaseEvidence& e, bool has_truth_pose) {
  if (e.found) return CaseStage::kFound;
  if (e.true_hypotheses.empty())
    return has_truth_pose && e.correct_correspondences >= 0 && e.correct_correspondences < 3
               ? CaseStage::kNoCorrectCorrespondence
               : CaseStage::kNoHypothesis;
  const auto any = [&](Verdict v) {
    return std::find(e.true_hypotheses.begin(), e.true_hypotheses.end(), v) !=
           e.true_hypotheses.end();
  };
  if (any(Verdict::kTakenByBetter) || any(Verdict::kKept)) return CaseStage::kOutranked;
  if (std::any_of(e.true_hypotheses.begin(), e.true_hypotheses.end(), FailedACheck))
    return CaseStage::kRejected;
  return CaseStage::kNotVerified;
}

bool SphereFitOptions::IsValid(std::string* error) const {
  if (!(min_radius_m > 0) || !(max_radius_m >= min_radius_m))
    return Fail(error, "radii must satisfy 0 < min_radius_m <= max_radius_m");
  if (!(inlier_distance_m > 0)) return Fail(error, "inlier_distance_m must be > 0");
  if (iterations < 1) return Fail(error, "iterations must be >= 1");
  return true;
}

namespace {

// The sphere through four points: |p|^2 + D x + E y + F z + G = 0, solved as a 4x4 system.
// nullopt when the points are (nearly) coplanar.
std::optional<Sphere> SphereThrough(const Eigen::Vector3f* p) {
  Eigen::Matrix4d a;
  Eigen::Vector4d b;
  for (int i = 0; i < 4; ++i) {
    a.row(i) << p[i].x(), p[i].y(), p[i].z(), 1.0;
    b(i) = -p[i].cast<double>().squaredNorm();
  }
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(a);
  if (lu.rank() < 4) return std::nullopt;
  const Eigen::Vector4d x = lu.solve(b);
  Sphere s;
  const Eigen::Vector3d c = -x.head<3>() / 2;
  const double r2 = c.squaredNorm() - x(3);
  if (!(r2 > 0)) return std::nullopt;
  s.centre_m = c.cast<float>();
  s.radius_m = static_cast<float>(std::sqrt(r2));
  return s;
}

// Least squares over many points, same algebraic form.
std::optional<Sphere> SphereThrough(const std::vector<Eigen::Vector3f>& points) {
  Eigen::MatrixXd a(points.size(), 4);
  Eigen::VectorXd b(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) << points[i].x(), points[i].y(), points[i].z(), 1.0;
    b(static_cast<Eigen::Index>(i)) = -points[i].cast<double>().squaredNorm();
  }
  const Eigen::Vector4d x = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector3d c = -x.head<3>() / 2;
  const double r2 = c.squaredNorm() - x(3);
  if (!(r2 > 0)) return std::nullopt;
  Sphere s;
  s.centre_m = c.cast<float>();
  s.radius_m = static_cast<float>(std::sqrt(r2));
  return s;
}

// Gauss-Newton on the geometric error sum (|p - c| - r)^2: the algebraic fit above is biased
// when only a noisy cap of the sphere is seen, as a depth camera sees it.
Sphere RefineGeometric(const std::vector<Eigen::Vector3f>& points, Sphere s) {
  for (int iteration = 0; iteration < 10; ++iteration) {
    Eigen::Matrix4d jtj = Eigen::Matrix4d::Zero();
    Eigen::Vector4d jte = Eigen::Vector4d::Zero();
    for (const Eigen::Vector3f& p : points) {
      const Eigen::Vector3d d = (p - s.centre_m).cast<double>();
      const double n = d.norm();
      if (n < 1e-9) continue;
      Eigen::Vector4d j;
      j << -d / n, -1.0;
      const double e = n - s.radius_m;
      jtj += j * j.transpose();
      jte += j * e;
    }
    const Eigen::Vector4d step = jtj.ldlt().solve(-jte);
    if (!step.allFinite()) break;
    s.centre_m += step.head<3>().cast<float>();
    s.radius_m += static_cast<float>(step(3));
    if (step.norm() < 1e-7) break;
  }
  return s;
}

}  // namespace

std::optional<Sphere> FitSphere(const Cloud& cloud, const SphereFitOptions& o) {
  std::vector<Eigen::Vector3f> points;
  for (const PointT& p : cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      points.push_back(p.getVector3fMap());
  if (points.size() < 4) return std::nullopt;
  std::mt19937 rng(o.seed);
  // Hypotheses are ranked on an even subset of at most kScored points (a VGA frame has 300k);
  // the refit uses them all.
  constexpr std::size_t kScored = 20000;
  std::vector<Eigen::Vector3f> scored;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / kScored);
  for (std::size_t i = 0; i < points.size(); i += stride) scored.push_back(points[i]);
  const auto inliers_of = [&](const Sphere& s, std::vector<Eigen::Vector3f>* out,
                              const std::vector<Eigen::Vector3f>& among) {
    std::size_t n = 0;
    for (const Eigen::Vector3f& p : among) {
      // Only the side facing the sensor can have been seen: this keeps out the ring of table
      // just beyond the contact under a ball, which would swell the radius.
      if ((p - s.centre_m).dot(o.viewpoint_m - p) <= 0) continue;
      if (std::abs((p - s.centre_m).norm() - s.radius_m) <= o.inlier_distance_m) {
        ++n;
        if (out) out->push_back(p);
      }
    }
    return n;
  };
  // Minimal samples come from one cell of a grid of r_max: points of one sphere lie close
  // together, and four points drawn from across a room almost never do.
  std::map<std::tuple<int, int, int>, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < scored.size(); ++i) {
    const Eigen::Vector3f c = scored[i] / o.max_radius_m;
    cells[{static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())),
           static_cast<int>(std::floor(c.z()))}]
        .push_back(i);
  }
  std::vector<const std::vector<std::size_t>*> cell_of(scored.size());
  for (const auto& [key, members] : cells)
    for (std::size_t i : members) cell_of[i] = &members;
  std::uniform_int_distribution<std::size_t> pick(0, scored.size() - 1);
  std::optional<Sphere> best;
  for (int it = 0; it < o.iterations; ++it) {
    const std::vector<std::size_t>& cell = *cell_of[pick(rng)];
    if (cell.size() < 4) continue;
    std::uniform_int_distribution<std::size_t> in_cell(0, cell.size() - 1);
    Eigen::Vector3f sample[4];
    for (auto& p : sample) p = scored[cell[in_cell(rng)]];
    std::optional<Sphere> s = SphereThrough(sample);
    if (!s || s->radius_m < o.min_radius_m || s->radius_m > o.max_radius_m) continue;
    s->inliers = inliers_of(*s, nullptr, scored);
    if (!best || s->inliers > best->inliers) best = s;
  }
  if (!best) return std::nullopt;
  best->inliers = inliers_of(*best, nullptr, points);
  // Refit on the inliers, twice: the first refit moves the set of inliers a little.
  for (int round = 0; round < 2; ++round) {
    std::vector<Eigen::Vector3f> in;
    inliers_of(*best, &in, points);
    std::optional<Sphere> refit = SphereThrough(in);
    if (refit) refit = RefineGeometric(in, *refit);
    if (!refit || refit->radius_m < o.min_radius_m || refit->radius_m > o.max_radius_m) break;
    refit->inliers = inliers_of(*refit, nullptr, points);
    best = refit;  // least squares over the inliers beats any four of them
  }
  return best;
}

}  // namespace saccade
