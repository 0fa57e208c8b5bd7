#include "io/sources/model_source.h"

#include "core/fail.h"
#include "core/sim/scenario.h"
#include "io/formats/cloud_io.h"
#include "io/sources/frame_source.h"

#include <cstdio>
#include <filesystem>

namespace saccade {

namespace {

bool IsFileSpec(const std::string& spec) {
  return spec.rfind("synthetic:", 0) != 0 && spec.rfind("capture:", 0) != 0;
}

}  // namespace

std::string ModelShortName(const std::string& spec) {
  const std::string stem = std::filesystem::path(spec).stem().string();
  return stem.empty() ? spec : stem;
}

std::optional<Cloud> LoadModelCloud(const std::string& spec, std::string* error) {
  for (const std::string name : {"target", "ball"}) {
    const std::string prefix = "synthetic:" + name;
    if (spec.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = spec.substr(prefix.size());
    unsigned seed = 1;
    char tail = 0;
    if (!rest.empty() && std::sscanf(rest.c_str(), "?seed=%u%c", &seed, &tail) != 1) {
      Fail(error, spec + ": expected " + prefix + " or " + prefix + "?seed=N");
      return std::nullopt;
    }
    return name == "target" ? SyntheticTargetModel(seed) : SyntheticBallModel(seed);
  }
  if (spec.rfind("capture:", 0) == 0) return LoadCaptureModel(spec, error);
  return LoadCloud(spec, error);
}

std::optional<std::vector<Cloud>> LoadModelViews(const std::string& spec, std::string* error) {
  if (IsFileSpec(spec)) return LoadCloudViews(spec, error);
  auto one = LoadModelCloud(spec, error);
  if (!one) return std::nullopt;
  return std::vector<Cloud>{std::move(*one)};
}

}  // namespace saccade
