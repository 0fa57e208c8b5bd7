// A peer for the evaluation: OpenCV's point-pair-feature matcher (cv::ppf_match_3d, Drost et
// al. 2010) run as its documentation runs it, so that its recall, false instances and time
// sit in the same table as Saccade's. It lives in this one translation unit, the only one
// that includes OpenCV.
#pragma once

#include "core/recognition.h"

#include <memory>
#include <optional>
#include <string>

namespace saccade {

/// OpenCV's sample (samples/ppf_load_match.cpp) but for the sampling step: its 0.025 took minutes
/// to train one mOSD model on this machine (training is quadratic in the sampled points), 0.05
/// takes about 16 s.
struct PpfPeerOptions {
  double relative_sampling_step = 0.05;            // of the model's extent, model and scene
  double relative_distance_step = 0.05;            // of the diameter: the feature's distance bin
  double relative_scene_sample_step = 1.0 / 40.0;  // share of scene points used as references
  int normal_neighbors = 10;                       // k of the normals it computes itself
  int instances = 1;                               // poses reported, most voted first
};

/// A model trained once by PPF3DDetector::trainModel. Immutable afterwards.
class PpfPeerModel {
 public:
  ~PpfPeerModel();
  PpfPeerModel(PpfPeerModel&&) noexcept;
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  friend std::optional<PpfPeerModel> TrainPpfPeer(const Cloud&, const PpfPeerOptions&,
                                                  std::string*);
  PpfPeerModel();
  std::unique_ptr<Impl> impl_;
};

/// nullopt with `error` when the model has too few finite points.
std::optional<PpfPeerModel> TrainPpfPeer(const Cloud& model, const PpfPeerOptions& options,
                                         std::string* error);

/// The best `options.instances` poses PPF3DDetector::match finds in the scene's finite points
/// (no verification; votes are its votes). Stage times: normals, match, total. Not safe to call
/// from two threads on one model at once (OpenCV's match keeps scratch state in the detector).
RecognitionResult RecognizePpfPeer(const PpfPeerModel& model, const Cloud& scene,
                                   const PpfPeerOptions& options);

}  // namespace saccade
