// A library: several models searched in one pass over a frame. Models whose fitted radii are
// the same (RecognitionOptions::library_radius_ratio puts them on one grid) share one
// description of the frame and one descriptor index: each scene descriptor is matched once, to
// its nearest descriptor of any model, so that a frame's cost grows with the number of radii,
// not of models, and a look-alike's descriptors compete with the object's instead of both
// winning. Each model then groups and verifies its own matches; where instances of two models
// claim one place, the more confident one stays (its colour agreement weighed in again: look-
// alikes differ in colour more than in shape).
#pragma once

#include "core/model.h"
#include "core/parallel.h"
#include "core/recognition.h"

#include <memory>
#include <string>
#include <vector>

namespace saccade {

struct LibraryResult {
  /// Every model's verified instances (Detection::model names it), best first; of instances of
  /// different models closer than half the smaller model's size, only the most confident
  /// (confidence plus half its colour agreement).
  std::vector<Detection> instances;
  std::vector<RecognitionResult> per_model;  // one per model; empty for a model not searched
  std::size_t scene_descriptions = 0;        // descriptions of the frame this search made
  /// Milliseconds per stage, summed over descriptions and models: describe (foveate,
  /// keypoints, normals, SHOT), match, group, verify.
  double describe_ms = 0, match_ms = 0, group_ms = 0, verify_ms = 0;
};

class Library;

/// Searches the scene for the library's models (`which[m]` false leaves model m out; empty:
/// all). Preconditions as Recognize's; `error` is set when the scene could not be processed.
LibraryResult RecognizeLibrary(const Library& library, const Cloud& scene, const SceneQuery& query,
                               const RecognitionOptions& options, const std::vector<bool>& which,
                               const ParallelFor& parallel_for = SerialFor,
                               std::string* error = nullptr);

class Library {
 public:
  /// `models` (not null) must outlive the library. `options` are those Recognize is given.
  Library(std::vector<const ModelDescription*> models, const RecognitionOptions& options);
  ~Library();
  Library(Library&&) noexcept;
  Library& operator=(Library&&) noexcept;

  std::size_t size() const { return models_.size(); }
  const ModelDescription& model(std::size_t i) const { return *models_[i]; }
  /// Descriptions of a frame a search of every model costs: the distinct radii.
  std::size_t Groups() const;

 private:
  friend LibraryResult RecognizeLibrary(const Library&, const Cloud&, const SceneQuery&,
                                        const RecognitionOptions&, const std::vector<bool>&,
                                        const ParallelFor&, std::string*);
  struct Group;
  std::vector<const ModelDescription*> models_;
  std::vector<Group> groups_;
};

/// How instances of different models that claim one place rank: confidence plus half the
/// colour agreement (none where colour was not measured). The higher stays.
float ArbitrationScore(const Detection& d);

/// Same place, different models: true when their centroids are closer than half the smaller of
/// the two models' sizes.
bool ClaimSamePlace(const Detection& a, float size_a, const Detection& b, float size_b);

}  // namespace saccade
