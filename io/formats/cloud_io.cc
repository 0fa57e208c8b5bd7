#include "io/formats/cloud_io.h"

#include "core/fail.h"
#include "core/foveation.h"
#include "io/formats/mesh_io.h"
#include "io/formats/pcd_check.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>

#include <sys/stat.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace saccade {

void QuietPcl() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }

namespace {

// Reads any PCD encoding into a blob; false with "PATH: reason" when missing, unreadable,
// corrupt, lying about its size, or without float x/y/z (CheckPcdFile).
// The VIEWPOINT (the sensor's pose when the cloud was taken) comes back in `origin` and
// `orientation`: normals are turned towards the origin, so a model saved with its capture's
// viewpoint must be loaded with it.
bool ReadBlob(const std::string& path, pcl::PCLPointCloud2* blob, Eigen::Vector4f* origin,
              Eigen::Quaternionf* orientation, std::string* error) {
  QuietPcl();
  // PCL's reader trusts what it reads: nothing reaches it that has not been checked whole.
  PcdHeader header;
  if (!CheckPcdFile(path, &header, error)) return false;
  pcl::PCDReader reader;
  int result = -1;
  int version = 0;
  try {
    result = reader.read(path, *blob, *origin, *orientation, version);
  } catch (const std::exception& e) {
    return Fail(error, path + ": not a readable PCD file (" + e.what() + ")");
  }
  if (result < 0) return Fail(error, path + ": not a readable PCD file (corrupt or truncated)");
  for (const char* axis : {"x", "y", "z"})
    if (pcl::getFieldIndex(*blob, axis) < 0)
      return Fail(error, path + ": PCD has no x, y and z fields");
  return true;
}

// The blob's points as XYZRGBA with the viewpoint it was read with (PCL's conversion resets it).
Cloud FromBlob(const pcl::PCLPointCloud2& blob, const Eigen::Vector4f& origin,
               const Eigen::Quaternionf& orientation) {
  Cloud cloud;
  pcl::fromPCLPointCloud2(blob, cloud);
  cloud.sensor_origin_ = origin;
  cloud.sensor_orientation_ = orientation;
  return cloud;
}

}  // namespace

std::optional<Cloud> LoadCloud(const std::string& path, std::string* error) {
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  if (!ReadBlob(path, &blob, &origin, &orientation, error)) {
    if (error && IsMeshPath(path))
      *error += " (a mesh: make a model of it with `saccade model --mesh " +
                std::filesystem::path(path).filename().string() + " --out MODEL.pcd`)";
    return std::nullopt;
  }
  return FromBlob(blob, origin, orientation);
}

std::optional<LabelledCloud> LoadLabelledCloud(const std::string& path, std::string* error) {
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  if (!ReadBlob(path, &blob, &origin, &orientation, error)) return std::nullopt;
  if (pcl::getFieldIndex(blob, "label") < 0) {
    Fail(error, path + ": PCD has no label field");
    return std::nullopt;
  }
  LabelledCloud out;
  out.cloud = FromBlob(blob, origin, orientation);
  pcl::PointCloud<pcl::Label> labels;
  pcl::fromPCLPointCloud2(blob, labels);
  out.labels.reserve(labels.size());
  for (const pcl::Label& l : labels) out.labels.push_back(l.label);
  return out;
}

namespace {

// Encoded in memory, written beside its place and renamed into it, so that a full disk or a
// failed write leaves no half file where a reader would take it for a whole one, and the error
// says why (PCL's own file writer loses errno).
bool SaveBlob(const std::string& path, const pcl::PCLPointCloud2& blob,
              const Eigen::Vector4f& origin, const Eigen::Quaternionf& orientation,
              std::string* error) {
  std::ostringstream encoded;
  pcl::PCDWriter writer;
  if (writer.writeBinaryCompressed(encoded, blob, origin, orientation) < 0)
    return Fail(error, path + ": cannot encode the cloud as a PCD file");
  return WriteBytes(path, encoded.str(), error);
}

constexpr const char* kViewpointFields[] = {"vp_x", "vp_y", "vp_z"};

}  // namespace

bool SaveCloud(const std::string& path, const Cloud& cloud, std::string* error) {
  QuietPcl();
  if (cloud.empty()) {
    return Fail(error, path + ": refusing to write an empty cloud");
  }
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(cloud, blob);
  return SaveBlob(path, blob, cloud.sensor_origin_, cloud.sensor_orientation_, error);
}

bool SaveModelViews(const std::string& path, const std::vector<Cloud>& views, std::string* error) {
  QuietPcl();
  if (views.size() == 1) return SaveCloud(path, views[0], error);
  Cloud all;
  std::vector<Eigen::Vector3f> origin_of;  // per point
  for (const Cloud& view : views) {
    for (const PointT& p : view.points) {
      if (!FinitePoint(p)) continue;
      all.push_back(p);
      origin_of.push_back(view.sensor_origin_.head<3>());
    }
  }
  if (all.empty()) return Fail(error, path + ": refusing to write an empty cloud");
  pcl::PCLPointCloud2 xyzrgba;
  pcl::toPCLPointCloud2(all, xyzrgba);
  // The same points with three more float fields: the sensor origin each was seen from.
  pcl::PCLPointCloud2 blob = xyzrgba;
  const std::uint32_t step = xyzrgba.point_step;
  for (std::uint32_t f = 0; f < 3; ++f) {
    pcl::PCLPointField field;
    field.name = kViewpointFields[f];
    field.offset = step + 4 * f;
    field.datatype = pcl::PCLPointField::FLOAT32;
    field.count = 1;
    blob.fields.push_back(field);
  }
  blob.point_step = step + 12;
  blob.row_step = blob.point_step * blob.width;
  blob.data.assign(std::size_t(blob.row_step) * blob.height, 0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::uint8_t* row = blob.data.data() + i * blob.point_step;
    std::memcpy(row, xyzrgba.data.data() + i * step, step);
    std::memcpy(row + step, origin_of[i].data(), 12);
  }
  const Box box = *BoundingBox(all);  // seen from all around: the origin inside says so
  return SaveBlob(path, blob, ((box.min + box.max) / 2).homogeneous(),
                  Eigen::Quaternionf::Identity(), error);
}

std::optional<std::vector<Cloud>> LoadCloudViews(const std::string& path, std::string* error) {
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  // A file is read once: a plain PCD is one view; what cannot be read is read again by
  // LoadCloud, for its error (and its hint when the file is a mesh).
  if (!ReadBlob(path, &blob, &origin, &orientation, nullptr)) {
    auto one = LoadCloud(path, error);
    if (!one) return std::nullopt;
    return std::vector<Cloud>{std::move(*one)};
  }
  if (pcl::getFieldIndex(blob, kViewpointFields[0]) < 0)
    return std::vector<Cloud>{FromBlob(blob, origin, orientation)};
  for (const char* name : kViewpointFields)
    if (const int f = pcl::getFieldIndex(blob, name);
        f < 0 || blob.fields[std::size_t(f)].datatype != pcl::PCLPointField::FLOAT32) {
      Fail(error, path + ": a model of several views needs float vp_x, vp_y and vp_z fields");
      return std::nullopt;
    }
  const Cloud all = FromBlob(blob, origin, orientation);
  pcl::PointCloud<pcl::PointWithViewpoint> seen_from;
  pcl::fromPCLPointCloud2(blob, seen_from);
  // Points seen from one sensor origin are one view, in the order the views first appear.
  std::vector<Cloud> views;
  std::vector<Eigen::Vector3f> origins;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Eigen::Vector3f o(seen_from[i].vp_x, seen_from[i].vp_y, seen_from[i].vp_z);
    if (!o.allFinite()) {
      Fail(error, path + ": point " + std::to_string(i) + " has no finite viewpoint");
      return std::nullopt;
    }
    std::size_t v = 0;
    while (v < origins.size() && origins[v] != o) ++v;
    if (v == origins.size()) {
      origins.push_back(o);
      views.emplace_back().sensor_origin_ = o.homogeneous();
    }
    views[v].push_back(all[i]);
  }
  if (views.empty()) {
    Fail(error, path + ": cloud has no valid point");
    return std::nullopt;
  }
  return views;
}

std::size_t CountFinite(const Cloud& cloud) {
  std::size_t n = 0;
  for (const auto& p : cloud.points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) ++n;
  return n;
}

std::optional<Eigen::Matrix4f> LoadPose(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    Fail(error, path + ": cannot open pose file");
    return std::nullopt;
  }
  std::vector<double> values;
  std::string line, token;
  std::ostringstream numbers;
  while (std::getline(in, line)) numbers << line.substr(0, line.find('#')) << '\n';  // # comments
  std::istringstream tokens(numbers.str());
  while (tokens >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) {
      Fail(error, path + ": '" + token + "' is not a finite number");
      return std::nullopt;
    }
    values.push_back(v);
  }
  if (values.size() != 16) {
    Fail(error,
         path + ": expected 16 numbers (a 4x4 matrix), found " + std::to_string(values.size()));
    return std::nullopt;
  }
  Eigen::Matrix4f pose;
  for (int i = 0; i < 16; ++i) pose(i / 4, i % 4) = static_cast<float>(values[i]);
  if (!pose.row(3).isApprox(Eigen::RowVector4f(0, 0, 0, 1), 1e-6f)) {
    Fail(error, path + ": last row must be 0 0 0 1");
    return std::nullopt;
  }
  const Eigen::Matrix3f R = pose.topLeftCorner<3, 3>();
  if (!(R * R.transpose()).isApprox(Eigen::Matrix3f::Identity(), 1e-3f) ||
      std::abs(R.determinant() - 1.0f) > 1e-3f) {
    Fail(error, path + ": the 3x3 block is not a proper rotation");
    return std::nullopt;
  }
  return pose;
}

}  // namespace saccade
