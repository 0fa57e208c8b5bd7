// PCL's stock correspondence-grouping stages, exactly as PCL's tutorial and the paper run them
// (k-NN normals over the whole cloud, UniformSampling, SHOTEstimation, BOARD frames, exact
// kd-tree matching, Hough3DGrouping). It is the plain "gold standard" Saccade is measured
// against; it lives in this one translation unit because its templates are heavy.
#pragma once

#include "core/recognition.h"

#include <memory>
#include <optional>
#include <string>

namespace saccade {

/// The model described by the stock stages, once. Immutable afterwards.
class ReferenceModel {
 public:
  ~ReferenceModel();
  ReferenceModel(ReferenceModel&&) noexcept;
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  friend std::optional<ReferenceModel> DescribeReferenceModel(const Cloud&,
                                                              const RecognitionOptions&,
                                                              std::string*);
  ReferenceModel();
  std::unique_ptr<Impl> impl_;
};

std::optional<ReferenceModel> DescribeReferenceModel(const Cloud& model,
                                                     const RecognitionOptions& options,
                                                     std::string* error);

/// Plain recognition with the stock stages and scene keypoint radius
/// options.scene_keypoint_radius_m. NaN descriptors and frames are dropped before matching and
/// grouping, and only proper rotations are reported.
RecognitionResult RecognizeReference(const ReferenceModel& model, const Cloud& scene,
                                     const RecognitionOptions& options,
                                     std::string* error = nullptr);

}  // namespace saccade
