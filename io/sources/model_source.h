// Where a model comes from: a model spec (a PCD file, the synthetic Kinect's objects, a capture
// sequence's object) read into the cloud, or the views, that recognition describes.
#pragma once

#include "core/types.h"

#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// A model by spec: a PCD path, or synthetic:target[?seed=N] / synthetic:ball[?seed=N] (the
/// synthetic Kinect's target or paper-protocol ball, captured alone; seed 1 by default), or
/// capture:FILE.yaml[?data=DIR] (a capture sequence's object, io/sources/frame_source.h).
/// Errors as LoadCloud (io/formats/cloud_io.h).
std::optional<Cloud> LoadModelCloud(const std::string& spec, std::string* error);

/// A model by spec (LoadModelCloud) as its views: a PCD with vp_x/vp_y/vp_z fields gives one
/// view per sensor origin, in order of first appearance; anything else is one view.
std::optional<std::vector<Cloud>> LoadModelViews(const std::string& spec, std::string* error);

/// A model's short name for people: its file name without folder and extension (mug for
/// /var/lib/saccade/models/mug.pcd); a spec without either (synthetic:target) as it is.
std::string ModelShortName(const std::string& spec);

}  // namespace saccade
