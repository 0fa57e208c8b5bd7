// A folder of the synthetic Kinect's frames as depth and colour images (what `saccade record
// --format depth` writes), for the virtual OpenNI2 device to serve.
#pragma once

#include "io/formats/frame_writer.h"
#include "io/sources/frame_source.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace saccade::testing {

/// Writes `frames` frames of synthetic:circular into `dir` (emptied first).
inline void WriteSyntheticDepthFolder(const std::string& dir, int frames) {
  std::filesystem::remove_all(dir);
  std::string error;
  auto source = OpenSource("synthetic:circular?rate=0&frames=" + std::to_string(frames), &error);
  ASSERT_TRUE(source) << error;
  auto writer = FrameWriter::Open(dir, FrameWriter::Format::kDepth, &error);
  ASSERT_TRUE(writer) << error;
  Frame f;
  while (source->Next(&f, &error) == FrameSource::Status::kFrame)
    ASSERT_TRUE(writer->Write(f, &error)) << error;
}

}  // namespace saccade::testing
