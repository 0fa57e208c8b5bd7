// The synthetic Kinect's demo case (seed 5: the target among clutter, and a model cut from
// another capture) with its model described under the default recognition options: built once
// per test binary, for the tracking tests that need a frame and a model with a known pose.
#pragma once

#include "core/recognition.h"
#include "core/sim/scenario.h"

#include <optional>
#include <string>

namespace saccade::testing {

struct DescribedDemo {
  DescribedDemo() : demo(MakeDemoCase(/*seed=*/5)) {
    std::string error;
    model.emplace(*DescribeModel(demo.model, RecognitionOptions{}, &error));
  }
  CrossCaptureCase demo;
  std::optional<ModelDescription> model;
};

inline const DescribedDemo& TheDescribedDemo() {
  static const DescribedDemo d;
  return d;
}

}  // namespace saccade::testing
