#include "core/candidates.h"

#include "core/check.h"
#include "core/fail.h"
#include "core/model.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <unordered_map>
#include <unordered_set>

namespace saccade {

bool CandidateOptions::IsValid(std::string* error) const {
  if (stride_px < 1 || stride_px > 64) return Fail(error, "stride_px must be in [1, 64]");
  if (!std::isfinite(z_max_m) || z_max_m <= 0) return Fail(error, "z_max_m must be > 0");
  if (!std::isfinite(plane_distance_m) || plane_distance_m <= 0 || plane_distance_m > 1)
    return Fail(error, "plane_distance_m must be in (0, 1]");
  if (!std::isfinite(min_plane_fraction) || min_plane_fraction < 0 || min_plane_fraction > 1)
    return Fail(error, "min_plane_fraction must be in [0, 1]");
  if (plane_iterations < 1 || plane_iterations > 100000)
    return Fail(error, "plane_iterations must be in [1, 100000]");
  if (max_candidates < 1 || max_candidates > 1000)
    return Fail(error, "max_candidates must be in [1, 1000]");
  if (!std::isfinite(colour_weight) || colour_weight < 0 || colour_weight > 1)
    return Fail(error, "colour_weight must be in [0, 1]");
  if (!std::isfinite(shape_weight) || shape_weight < 0 || shape_weight > 1)
    return Fail(error, "shape_weight must be in [0, 1]");
  if (!std::isfinite(apart_weight) || apart_weight < 0 || apart_weight > 1)
    return Fail(error, "apart_weight must be in [0, 1]");
  return true;
}

namespace {

// A bin of the model's histogram holding this share of its points or more is fully its colour.
constexpr float kFullColourShare = 1.0f / 32;
// A whole surface's silhouette is drawn on cells this many point spacings across: wide enough
// that its points leave no holes, narrow enough to add little at its outline.
constexpr float kSilhouetteCells = 1.5f;

struct Sample {
  Eigen::Vector3f p;
  int bin;  // ColourBin, -1 when too dark
};

// The largest plane of the samples by RANSAC (seeded), refit by least squares on its inliers:
// (n, d) with n.p + d = 0, or nullopt when no plane holds min_plane_fraction of them.
std::optional<Eigen::Vector4f> LargestPlane(const std::vector<Sample>& samples,
                                            const CandidateOptions& o) {
  if (samples.size() < 3) return std::nullopt;
  std::mt19937 rng(o.seed);
  std::uniform_int_distribution<std::size_t> pick(0, samples.size() - 1);
  // Hypotheses are scored on an even subset; the winner is counted and refit on all.
  const std::size_t step = std::max<std::size_t>(1, samples.size() / 2000);
  Eigen::Vector4f best = Eigen::Vector4f::Zero();
  std::size_t best_count = 0;
  for (int it = 0; it < o.plane_iterations; ++it) {
    const Eigen::Vector3f a = samples[pick(rng)].p, b = samples[pick(rng)].p,
                          c = samples[pick(rng)].p;
    Eigen::Vector3f n = (b - a).cross(c - a);
    if (n.norm() < 1e-9f) continue;
    n.normalize();
    const float d = -n.dot(a);
    std::size_t count = 0;
    for (std::size_t i = 0; i < samples.size(); i += step)
      count += std::abs(n.dot(samples[i].p) + d) <= o.plane_distance_m;
    if (count > best_count) best_count = count, best = Eigen::Vector4f(n.x(), n.y(), n.z(), d);
  }
  if (best_count == 0) return std::nullopt;
  const auto inliers = [&](const Eigen::Vector4f& plane, Eigen::Vector3f* mean,
                           Eigen::Matrix3f* scatter) {
    std::size_t n = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    for (const Sample& s : samples) {
      if (std::abs(plane.head<3>().dot(s.p) + plane[3]) > o.plane_distance_m) continue;
      ++n;
      const Eigen::Vector3d p = s.p.cast<double>();
      sum += p;
      outer += p * p.transpose();
    }
    if (n > 0 && mean) {
      const Eigen::Vector3d m = sum / double(n);
      *mean = m.cast<float>();
      *scatter = (outer / double(n) - m * m.transpose()).cast<float>();
    }
    return n;
  };
  Eigen::Vector3f mean;
  Eigen::Matrix3f scatter;
  const std::size_t count = inliers(best, &mean, &scatter);
  if (float(count) < o.min_plane_fraction * float(samples.size()) || count < 3) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(scatter);
  const Eigen::Vector3f n = eig.eigenvectors().col(0).normalized();
  return Eigen::Vector4f(n.x(), n.y(), n.z(), -n.dot(mean));
}

struct Cell {
  int points = 0;
  float weight = 0;                                    // sum of colour weights
  Eigen::Vector3f weighted = Eigen::Vector3f::Zero();  // sum of weight x position
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();       // sum of positions
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();     // sum of position x position'
};

// The root of the least eigenvalue of the covariance of `n` points with these sums: how far
// they spread across their flattest direction.
float Thickness(int n, const Eigen::Vector3d& sum, const Eigen::Matrix3d& outer) {
  if (n < 3) return 0;
  const Eigen::Vector3d mean = sum / double(n);
  const Eigen::Matrix3d covariance = outer / double(n) - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(covariance, Eigen::EigenvaluesOnly);
  return float(std::sqrt(std::max(0.0, eig.eigenvalues()(0))));
}

std::int64_t CellKey(int x, int y, int z) {
  constexpr std::int64_t kSpan = 1 << 20;  // +-2^19 cells each way
  return ((std::int64_t(x) + kSpan / 2) * kSpan + (std::int64_t(y) + kSpan / 2)) * kSpan +
         (std::int64_t(z) + kSpan / 2);
}

}  // namespace

namespace {

// What a whole surface shows from one side: the area of its silhouette and the thickness of the
// part a depth sensor returns of it.
struct SideView {
  float area_m2 = 0;
  float thickness_m = 0;
};

// The model seen along `sides` directions spread evenly over the sphere. The silhouette: the
// cloud's points projected across the direction onto cells of `cell_m`. The surface seen: the
// points of `surface` whose normals face the viewer at least as squarely as a sensor needs
// (VerificationModel::min_facing; a face seen nearly edge-on returns little).
std::vector<SideView> LookFromAllSides(const Cloud& cloud, const VerificationModel& surface,
                                       float cell_m, int sides) {
  std::vector<SideView> out;
  const float golden = float(M_PI) * (3.0f - std::sqrt(5.0f));
  const float facing = std::max(0.0f, surface.min_facing);
  std::unordered_set<std::int64_t> covered;
  for (int i = 0; i < sides; ++i) {
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(sides);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const Eigen::Vector3f d(r * std::cos(golden * float(i)), r * std::sin(golden * float(i)), z);
    const Eigen::Vector3f u = d.unitOrthogonal(), v = d.cross(u);
    covered.clear();
    for (const PointT& p : cloud)
      if (FinitePoint(p))
        covered.insert(CellKey(int(std::floor(p.getVector3fMap().dot(u) / cell_m)),
                               int(std::floor(p.getVector3fMap().dot(v) / cell_m)), 0));
    int n = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < surface.points.size() && k < surface.normals.size(); ++k) {
      if (!(-surface.normals[k].dot(d) > facing)) continue;  // d points away from the viewer
      const Eigen::Vector3d q = surface.points[k].getVector3fMap().cast<double>();
      ++n;
      sum += q;
      outer += q * q.transpose();
    }
    out.push_back({float(covered.size()) * cell_m * cell_m, Thickness(n, sum, outer)});
  }
  return out;
}

// The value at `share` of the way through `sorted`.
float Quantile(const std::vector<float>& sorted, float share) {
  return sorted.empty() ? 0 : sorted[std::size_t(share * float(sorted.size() - 1) + 0.5f)];
}

}  // namespace

ModelSignature SignModel(const Cloud& model, float spacing_m, const VerificationModel* surface) {
  ModelSignature s;
  Box box{Eigen::Vector3f::Constant(INFINITY), Eigen::Vector3f::Constant(-INFINITY)};
  int finite = 0, coloured = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (const PointT& p : model) {
    if (!FinitePoint(p)) continue;
    ++finite;
    box.min = box.min.cwiseMin(p.getVector3fMap());
    box.max = box.max.cwiseMax(p.getVector3fMap());
    const Eigen::Vector3d q = p.getVector3fMap().cast<double>();
    sum += q;
    outer += q * q.transpose();
    coloured += (p.r | p.g | p.b) != 0;
    AddColour(p, &s.colour);
  }
  if (finite == 0) return s;
  s.radius_m = 0.5f * box.Size().norm();
  s.seen_area_m2 = float(finite) * spacing_m * spacing_m;
  s.thickness_m = Thickness(finite, sum, outer);
  if (surface && surface->whole_surface && surface->min_facing <= 0) {
    // Captures of several sides, seen half at a time: their silhouettes, from estimated normals
    // and views that leave gaps, lost cases on the benchmark's models of other captures.
    s.seen_area_m2 *= 0.5f;
    s.thickness_m *= 0.5f;
  }
  s.seen_area_min_m2 = s.seen_area_max_m2 = s.seen_area_m2;
  if (surface && surface->whole_surface && surface->min_facing > 0) {
    constexpr int kSides = 64;
    const std::vector<SideView> sides =
        LookFromAllSides(model, *surface, std::max(1e-4f, kSilhouetteCells * spacing_m), kSides);
    std::vector<float> areas, thicknesses;
    for (const SideView& v : sides)
      areas.push_back(v.area_m2), thicknesses.push_back(v.thickness_m);
    std::sort(areas.begin(), areas.end());
    std::sort(thicknesses.begin(), thicknesses.end());
    s.seen_area_min_m2 = Quantile(areas, 0.0f);
    s.seen_area_m2 = Quantile(areas, 0.5f);
    s.seen_area_max_m2 = Quantile(areas, 1.0f);
    s.thickness_m = Quantile(thicknesses, 0.5f);
    s.silhouettes = true;
  }
  // A model without colour reads as all black: every point too dark for a chromaticity.
  float counted = 0;
  for (float v : s.colour) counted += v;
  s.coloured = coloured > 0 && counted >= 0.2f * float(finite) && !MaterialGreys(model);
  Normalize(&s.colour);
  return s;
}

ModelSignature SignModel(const ModelDescription& model) {
  return SignModel(model.cloud(), model.scale().spacing_m, &model.verification());
}

std::optional<Eigen::Vector4f> TablePlane(const Cloud& organized, const CandidateOptions& o) {
  if (!organized.isOrganized() || organized.empty()) return std::nullopt;
  std::vector<Sample> samples;
  std::size_t pixels = 0;
  for (std::uint32_t v = 0; v < organized.height; v += o.stride_px)
    for (std::uint32_t u = 0; u < organized.width; u += o.stride_px) {
      ++pixels;
      const PointT& p = organized(u, v);
      if (FinitePoint(p) && p.z > 0 && p.z <= o.z_max_m)
        samples.push_back({p.getVector3fMap(), -1});
    }
  const auto plane = LargestPlane(samples, o);
  if (!plane) return std::nullopt;
  // A table spans a share of the image, not only of what was seen: an object cut out of its
  // frame (NaN around it) has a largest face, and it is no table.
  const std::size_t on = std::count_if(samples.begin(), samples.end(), [&](const Sample& s) {
    return std::abs(plane->head<3>().dot(s.p) + (*plane)[3]) <= o.plane_distance_m;
  });
  if (float(on) < o.min_plane_fraction * float(pixels)) return std::nullopt;
  return plane;
}

std::vector<Candidate> ProposeCandidates(const Cloud& organized, const CameraIntrinsics& intrinsics,
                                         const ModelSignature& model, const CandidateOptions& o,
                                         CandidateStats* stats) {
  SACCADE_CHECK_VALID(o);
  SACCADE_CHECK(model.radius_m > 0, "ProposeCandidates: the model has no extent");
  CandidateStats local;
  CandidateStats& st = stats ? *stats : local;
  st = CandidateStats{};
  if (!organized.isOrganized() || organized.empty()) return {};

  // 1. The coarse view.
  std::vector<Sample> samples;
  samples.reserve((organized.width / o.stride_px + 1) * (organized.height / o.stride_px + 1));
  std::size_t dark = 0;
  for (std::uint32_t v = 0; v < organized.height; v += o.stride_px)
    for (std::uint32_t u = 0; u < organized.width; u += o.stride_px) {
      const PointT& p = organized(u, v);
      if (!FinitePoint(p) || p.z <= 0 || p.z > o.z_max_m) continue;
      samples.push_back({p.getVector3fMap(), ColourBin(p)});
      dark += samples.back().bin < 0;
    }
  st.coarse_points = int(samples.size());

  // 2. Off the table, on the camera's side (the camera is at the origin: its side is d's sign).
  const std::optional<Eigen::Vector4f> plane = LargestPlane(samples, o);
  st.plane_found = plane.has_value();
  if (plane) {
    const float side = (*plane)[3] >= 0 ? 1.0f : -1.0f;
    samples.erase(std::remove_if(samples.begin(), samples.end(),
                                 [&](const Sample& s) {
                                   const float h = side * (plane->head<3>().dot(s.p) + (*plane)[3]);
                                   return h <= o.plane_distance_m;
                                 }),
                  samples.end());
  }
  st.above_plane = int(samples.size());
  if (samples.empty()) return {};

  // 3. Colour weights: how much the model has of each point's colour. A frame without colour
  // (every point dark) or a model without it: geometry alone.
  const bool colour = model.coloured && dark < samples.size() / 2 + samples.size() / 4;
  std::array<float, 64> weight;
  for (std::size_t b = 0; b < weight.size(); ++b)
    weight[b] = std::min(1.0f, model.colour[b] / kFullColourShare);
  const auto weigh = [&](const Sample& s) {
    if (!colour) return 1.0f;
    return s.bin < 0 ? 0.5f : weight[s.bin];  // too dark to tell: half
  };

  // 4. Cells of half the model's radius; windows of the cells within the radius of each.
  const float cell_m = std::max(0.01f, 0.5f * model.radius_m);
  std::unordered_map<std::int64_t, Cell> cells;
  cells.reserve(samples.size() / 4 + 16);
  std::vector<std::array<int, 3>> coords;
  for (const Sample& s : samples) {
    const Eigen::Vector3i c = (s.p / cell_m).array().floor().cast<int>();
    auto [it, fresh] = cells.try_emplace(CellKey(c.x(), c.y(), c.z()));
    if (fresh) coords.push_back({c.x(), c.y(), c.z()});
    Cell& cell = it->second;
    const float w = weigh(s);
    ++cell.points;
    cell.weight += w;
    cell.weighted += w * s.p;
    cell.sum += s.p;
    const Eigen::Vector3d q = s.p.cast<double>();
    cell.outer += q * q.transpose();
  }
  // A window: the cells within 2 of its centre; its shell: those from 2 to 2.83 away.
  std::vector<std::array<int, 3>> offsets, shell;
  for (int dx = -2; dx <= 2; ++dx)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dz = -2; dz <= 2; ++dz) {
        const int d2 = dx * dx + dy * dy + dz * dz;
        if (d2 <= 4)
          offsets.push_back({dx, dy, dz});
        else if (d2 <= 8)
          shell.push_back({dx, dy, dz});
      }
  // A coarse sample at depth z stands for (stride z / f)^2 of surface facing the camera.
  const float focal = float(0.5 * (intrinsics.fx + intrinsics.fy)) / float(o.stride_px);
  const float cw = colour ? o.colour_weight : 0.0f;
  const float sw = model.thickness_m > 0 ? o.shape_weight : 0.0f;
  // An object on the table loses a strip of plane_distance_m off its bottom with the table: a
  // silhouette as wide as it is tall, the square root of its area.
  const float least_area =
      plane && model.silhouettes
          ? std::max(
                0.5f * model.seen_area_min_m2,
                model.seen_area_min_m2 - o.plane_distance_m * std::sqrt(model.seen_area_min_m2))
          : model.seen_area_min_m2;
  // A whole surface's amount says only that a window lies within its sides' range of areas: the
  // wider that range, the more standing apart has to tell (a one-sided model's share stays
  // apart_weight).
  const float aw =
      model.seen_area_max_m2 > 0
          ? std::clamp(1 - (1 - o.apart_weight) * (model.seen_area_min_m2 / model.seen_area_max_m2),
                       o.apart_weight, 1.0f)
          : o.apart_weight;
  std::vector<Candidate> windows;
  windows.reserve(coords.size());
  for (const auto& c : coords) {
    Cell w;
    for (const auto& d : offsets) {
      const auto it = cells.find(CellKey(c[0] + d[0], c[1] + d[1], c[2] + d[2]));
      if (it == cells.end()) continue;
      w.points += it->second.points;
      w.weight += it->second.weight;
      w.weighted += it->second.weighted;
      w.sum += it->second.sum;
      w.outer += it->second.outer;
    }
    Candidate k;
    k.points = w.points;
    const Eigen::Vector3f mean = w.sum / float(w.points);
    const float pixels_per_m2 = (focal / mean.z()) * (focal / mean.z());
    const float least = std::max(1.0f, least_area * pixels_per_m2);
    const float most = std::max(least, model.seen_area_max_m2 * pixels_per_m2);
    // As much as the model would cover there from some side: a smaller object, or a part of a
    // larger one (whose window holds more), matches less.
    k.fill = std::min({1.0f, float(w.points) / least, most / float(w.points)});
    k.colour = w.weight / float(w.points);
    if (sw > 0)
      k.shape =
          std::min(1.0f, Thickness(w.points, w.sum.cast<double>(), w.outer) / model.thickness_m);
    if (aw > 0) {
      int around = 0;
      for (const auto& d : shell) {
        const auto it = cells.find(CellKey(c[0] + d[0], c[1] + d[1], c[2] + d[2]));
        if (it != cells.end()) around += it->second.points;
      }
      k.apart = std::max(0.0f, 1.0f - float(around) / float(w.points));
    }
    k.score =
        k.fill * ((1 - sw) + sw * k.shape) * ((1 - cw) + cw * k.colour) * ((1 - aw) + aw * k.apart);
    k.centre_m = w.weight > 0 ? Eigen::Vector3f(w.weighted / w.weight) : mean;
    windows.push_back(k);
  }

  // 5. The best windows, none within the model's radius of a better one.
  std::sort(windows.begin(), windows.end(), [](const Candidate& a, const Candidate& b) {
    if (a.score != b.score) return a.score > b.score;
    if (a.colour != b.colour) return a.colour > b.colour;
    return a.points > b.points;
  });
  std::vector<Candidate> out;
  for (const Candidate& k : windows) {
    if (int(out.size()) >= o.max_candidates) break;
    if (std::any_of(out.begin(), out.end(), [&](const Candidate& c) {
          return (c.centre_m - k.centre_m).norm() < model.radius_m;
        }))
      continue;
    out.push_back(k);
  }
  return out;
}

}  // namespace saccade
