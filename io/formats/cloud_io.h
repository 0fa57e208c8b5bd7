// Reading and writing clouds and poses. Every failure comes back as one line naming the file.
#pragma once

#include "core/types.h"
#include "io/formats/output_file.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// Loads a PCD file (any PCL encoding) into XYZRGBA; colour is zero when the file has none.
/// nullopt with `error` = "PATH: reason" when missing, unreadable, corrupt or without x/y/z.
std::optional<Cloud> LoadCloud(const std::string& path, std::string* error);

/// A cloud with a per-point integer label (as the mOSD scenes: 0 invalid, 1-9 table, 10k+j
/// part j of object k); labels.size() == cloud.size().
struct LabelledCloud {
  Cloud cloud;
  std::vector<std::uint32_t> labels;
};

/// Loads a PCD file with a `label` field; errors as LoadCloud, and when there is no label field.
std::optional<LabelledCloud> LoadLabelledCloud(const std::string& path, std::string* error);

/// Writes a binary-compressed PCD; false with `error` on failure.
bool SaveCloud(const std::string& path, const Cloud& cloud, std::string* error);

/// A model of several views (core/model.h): each view's points in the model frame with its
/// sensor origin. Written as one PCD of every point with the origin it was seen from in the
/// fields vp_x, vp_y, vp_z (PCL's PointWithViewpoint layout) and a VIEWPOINT inside the points
/// (seen from all around); any PCD reader takes it as the merged surface. One view is SaveCloud.
bool SaveModelViews(const std::string& path, const std::vector<Cloud>& views, std::string* error);

/// A PCD file as the views of a model (SaveModelViews): with vp_x/vp_y/vp_z fields, one view
/// per sensor origin in order of first appearance; any other PCD is one view. Errors as
/// LoadCloud.
std::optional<std::vector<Cloud>> LoadCloudViews(const std::string& path, std::string* error);

/// Number of points with finite x, y and z.
std::size_t CountFinite(const Cloud& cloud);

/// Reads a 4x4 homogeneous matrix written as 16 numbers (rows in order, any whitespace);
/// the last row must be 0 0 0 1 and the rotation proper.
std::optional<Eigen::Matrix4f> LoadPose(const std::string& path, std::string* error);

/// Silences PCL's own console messages, so that errors reach the user once, as ours.
void QuietPcl();

}  // namespace saccade
