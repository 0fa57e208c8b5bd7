#include "core/neighbor_search.h"

#include <pcl/kdtree/kdtree_flann.h>

#include <algorithm>
#include <cmath>

namespace saccade {
namespace {

class OrganizedSearch final : public NeighborSearch {
 public:
  OrganizedSearch(const Cloud& cloud, const CameraIntrinsics& k,
                  const std::vector<std::uint8_t>& mask, int max_half_window_px)
      : cloud_(cloud), k_(k), mask_(mask), max_half_(max_half_window_px) {}

  void Radius(int query, float r, std::vector<int>* indices,
              std::vector<float>* sqr_dists) const override {
    indices->clear();
    sqr_dists->clear();
    const int w = static_cast<int>(cloud_.width), h = static_cast<int>(cloud_.height);
    const Eigen::Vector3f q = cloud_[query].getVector3fMap();
    // The sphere's image footprint is widest at its nearest depth.
    const float z_near = std::max(q.z() - r, 0.05f);
    const int hu = static_cast<int>(std::ceil(r * k_.fx / z_near)) + 1;
    const int hv = static_cast<int>(std::ceil(r * k_.fy / z_near)) + 1;
    // A window wider than the limit is sampled every `step` pixels, so that the support holds
    // about as many points as the limit's window would. The samples lie on one image-wide grid
    // (multiples of `step`), not on one through each query: neighbouring keypoints then share
    // their samples, and normals are needed only on that grid (SupportMask).
    const int step = max_half_ > 0 ? (std::max(hu, hv) + max_half_ - 1) / max_half_ : 1;
    const int u0 = query % w, v0 = query / w;
    const auto first = [step](int at, int half) {
      return (std::max(0, at - half) + step - 1) / step * step;
    };
    const int u_lo = first(u0, hu), u_hi = std::min(w - 1, u0 + hu);
    const int v_lo = first(v0, hv), v_hi = std::min(h - 1, v0 + hv);
    const float r2 = r * r;
    for (int v = v_lo; v <= v_hi; v += step) {
      const int row = v * w;
      for (int u = u_lo; u <= u_hi; u += step) {
        const int i = row + u;
        if (!mask_[i]) continue;
        const float d2 = (cloud_[i].getVector3fMap() - q).squaredNorm();
        if (d2 <= r2) {  // NaN compares false
          indices->push_back(i);
          sqr_dists->push_back(d2);
        }
      }
    }
  }

 private:
  const Cloud& cloud_;
  const CameraIntrinsics k_;
  const std::vector<std::uint8_t>& mask_;
  const int max_half_;  // 0: every pixel of the window
};

class KdTreeSearch final : public NeighborSearch {
 public:
  KdTreeSearch(const Cloud& cloud, const std::vector<std::uint8_t>& mask) : cloud_(cloud) {
    auto kept = std::make_shared<pcl::Indices>();
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (mask[i] && FinitePoint(cloud[i])) kept->push_back(static_cast<int>(i));
    // The tree shares the cloud without owning it: the caller keeps it alive.
    tree_.setInputCloud(Cloud::ConstPtr(&cloud, [](const Cloud*) {}), kept);
  }

  void Radius(int query, float r, std::vector<int>* indices,
              std::vector<float>* sqr_dists) const override {
    indices->clear();
    sqr_dists->clear();
    pcl::Indices found;
    tree_.radiusSearch(cloud_[query], r, found, *sqr_dists);
    indices->assign(found.begin(), found.end());
  }

 private:
  const Cloud& cloud_;
  pcl::KdTreeFLANN<PointT> tree_;
};

}  // namespace

std::unique_ptr<NeighborSearch> MakeOrganizedSearch(const Cloud& cloud,
                                                    const CameraIntrinsics& intrinsics,
                                                    const std::vector<std::uint8_t>& mask,
                                                    int max_half_window_px) {
  return std::make_unique<OrganizedSearch>(cloud, intrinsics, mask, max_half_window_px);
}

std::unique_ptr<NeighborSearch> MakeKdTreeSearch(const Cloud& cloud,
                                                 const std::vector<std::uint8_t>& mask) {
  return std::make_unique<KdTreeSearch>(cloud, mask);
}

}  // namespace saccade
