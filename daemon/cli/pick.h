// Which segmented cluster is the object: saccade segment's and saccade model --captures' --pick.
#pragma once

#include "core/segmentation.h"

#include <cstddef>
#include <optional>
#include <string>

namespace saccade {

/// --pick largest|nearest|N, parsed before any work is done.
struct PickRule {
  enum class Kind { kLargest, kNearest, kIndex } kind = Kind::kLargest;
  std::size_t index = 0;
};

/// nullopt when `text` is none of largest, nearest or a cluster index.
std::optional<PickRule> ParsePick(const std::string& text);

/// The cluster the rule picks (clusters come largest first; nearest: centroid nearest the
/// camera), or nullopt with `error` when the index is out of range.
std::optional<std::size_t> Pick(const PickRule& rule, const Segmentation& s, std::string* error);

}  // namespace saccade
