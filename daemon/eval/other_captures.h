// Models from other captures (saccade eval --model-source other-captures): each case's model is
// made of every other capture of its object in the cases file, never the scene's own capture,
// aligned into one frame (core/view_alignment.h). Each capture is one view of the model: a
// scene showing a side that one capture missed can be found from another's.
#pragma once

#include "core/camera.h"
#include "core/parallel.h"
#include "core/types.h"
#include "core/view_alignment.h"
#include "io/config/config.h"

#include <Eigen/Core>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace saccade::eval {

/// One object in one capture: the file and its mOSD object number.
using CaptureKey = std::pair<std::string, int>;

/// Labelled captures read once, and their objects cut once: the object's points where the
/// capture has them, NaN elsewhere (organized: an alignment checks what the camera saw
/// through).
class CaptureCuts {
 public:
  struct Capture {
    std::shared_ptr<const Cloud> cloud;
    std::vector<std::uint32_t> labels;
    CameraIntrinsics intrinsics;  // estimated from the organized cloud
  };
  /// `context` (the cases file) names where a missing object was asked for.
  explicit CaptureCuts(std::string context) : context_(std::move(context)) {}
  /// nullptr with `error` set when the file cannot be read.
  const Capture* Load(const std::string& file, std::string* error);
  /// nullptr with `error` set when the file cannot be read or has no such object.
  const Cloud* Cut(const CaptureKey& key, std::string* error);

 private:
  std::string context_;
  std::map<std::string, Capture> loaded_;
  std::map<CaptureKey, Cloud> cuts_;
};

/// A model of several captures and what the truth says of it.
struct ViewsModel {
  std::vector<Cloud> views;          // in the reference capture's frame, sensor origins set
  std::vector<CaptureKey> captures;  // one per view
  CaptureKey reference;
  int left_out = 0;  // other captures that no alignment reached
  /// The reference capture's frame to the scene capture's, chained through the cases' truth
  /// poses when they connect the two; nullopt when they do not.
  std::optional<Eigen::Matrix4f> truth_pose;
};

/// Builds, for each scene capture of each identity, the model of every other capture of that
/// identity in `all` (the whole cases file). `cut` gives a capture's object points (camera
/// frame). Captures are aligned pairwise once per identity (in parallel); each model chains
/// its captures from the best connected one. `log` gets one line per identity.
class OtherCaptureModels {
 public:
  using Cut = std::function<const Cloud*(const CaptureKey&)>;
  OtherCaptureModels(const std::vector<LabelledCase>& all, AlignmentOptions options, Cut cut,
                     ParallelFor parallel, std::ostream* log);
  /// The model searching `scene` of `identity`; nullopt with `error` when no other capture of
  /// it can be described.
  std::optional<ViewsModel> For(const std::string& identity, const CaptureKey& scene,
                                std::string* error);
  /// The model of `identity` from every capture of it that is not in `file` (all of them when
  /// none is): a library's model searching that capture.
  std::optional<ViewsModel> ForFile(const std::string& identity, const std::string& file,
                                    std::string* error);
  /// The identities, by name.
  std::vector<std::string> Identities() const;

 private:
  struct Identity {
    std::vector<CaptureKey> captures;
    std::vector<std::vector<ViewAlignment>> pairs;  // pairs[a][b]: a aligned to b
    bool aligned = false;
  };
  bool Align(Identity* id);  // false when a capture cannot be cut (the cut says why)
  std::optional<ViewsModel> Build(const std::string& identity, const CaptureKey& scene,
                                  const std::function<bool(const CaptureKey&)>& excluded,
                                  std::string* error);

  std::map<std::string, Identity> identities_;
  std::map<std::pair<CaptureKey, CaptureKey>, Eigen::Matrix4f> truth_;  // model -> scene
  AlignmentOptions options_;
  Cut cut_;
  ParallelFor parallel_;
  std::ostream* log_;
};

}  // namespace saccade::eval
