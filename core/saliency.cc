#include "core/saliency.h"

#include "core/fail.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace saccade {

bool SaliencyOptions::IsValid(std::string* error) const {
  if (stride_px < 1) return Fail(error, "stride_px must be >= 1");
  if (!(cell_m > 0)) return Fail(error, "cell_m must be > 0");
  if (!(edge_jump_m > 0)) return Fail(error, "edge_jump_m must be > 0");
  if (max_regions < 1) return Fail(error, "max_regions must be >= 1");
  return true;
}

std::vector<Eigen::Vector3f> SalientRegions(const Cloud& cloud, const SaliencyOptions& options) {
  if (cloud.height <= 1 || options.stride_px < 1 || options.cell_m <= 0) return {};
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  const int s = options.stride_px;
  const auto at = [&](int u, int v) -> const PointT& { return cloud.points[v * w + u]; };
  // On a plane, inverse depth is affine in the pixel coordinates, so its second difference
  // is zero however slanted the plane (a table seen at a grazing angle); at the near side of
  // a depth edge it is strongly negative. Scaled by z^2 it reads as a depth step in metres.
  const auto near_side_of_edge = [&](const PointT& p, int u, int v) {
    for (const auto& [du, dv] : {std::pair{s, 0}, std::pair{0, s}}) {
      if (u - du < 0 || v - dv < 0 || u + du >= w || v + dv >= h) continue;
      const float za = at(u - du, v - dv).z, zb = at(u + du, v + dv).z;
      // A neighbour with no return says nothing: shadows and the void edge every surface.
      if (!std::isfinite(za) || !std::isfinite(zb)) continue;
      const float step = (1 / za + 1 / zb - 2 / p.z) * p.z * p.z;
      if (step < -options.edge_jump_m) return true;
    }
    return false;
  };
  struct Cell {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    int count = 0;
  };
  std::map<std::tuple<int, int, int>, Cell> cells;  // ordered: ties rank the same every run
  for (int v = 0; v < h; v += s) {
    for (int u = 0; u < w; u += s) {
      const PointT& p = at(u, v);
      if (!std::isfinite(p.z) || !near_side_of_edge(p, u, v)) continue;
      const Eigen::Vector3f x = p.getVector3fMap();
      const auto key = std::make_tuple(static_cast<int>(std::floor(x.x() / options.cell_m)),
                                       static_cast<int>(std::floor(x.y() / options.cell_m)),
                                       static_cast<int>(std::floor(x.z() / options.cell_m)));
      Cell& c = cells[key];
      c.sum += x;
      ++c.count;
    }
  }
  std::vector<const Cell*> ranked;
  for (const auto& [key, cell] : cells) ranked.push_back(&cell);
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const Cell* a, const Cell* b) { return a->count > b->count; });
  std::vector<Eigen::Vector3f> regions;
  for (const Cell* c : ranked) {
    if (static_cast<int>(regions.size()) >= options.max_regions) break;
    regions.push_back(c->sum / static_cast<float>(c->count));
  }
  return regions;
}

}  // namespace saccade
