// libFuzzer target: the decoders of what arrives over LCM, on arbitrary bytes: the command
// decoder (DecodeCommand in io/bus.h, what the command channel delivers to the daemon), and
// the fixation and detections decoders the log converters use (io/fixation_log.h,
// io/detections_log.h), and the viewer's state fed the bytes on each of its channels
// (io/viewer.h: detections, fixation, status and preview, io/preview.h). Each must return a
// message or refuse, never crash.
#include "io/bus.h"
#include "io/detections_log.h"
#include "io/fixation_log.h"
#include "io/viewer.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string why;
  const auto command = saccade::DecodeCommand(data, size, saccade::BusOptions{},
                                              Eigen::Isometry3f::Identity(), &why);
  if (!command && (why.empty() || why.find('\n') != std::string::npos)) __builtin_trap();
  // The same bytes as the other messages: what decodes is also written, as the converters do.
  std::ostringstream out;
  saccade::LoggedFixation fixation;
  if (saccade::DecodeFixation(data, size, &fixation))
    saccade::FixationWriter(out, saccade::TableFormat::kCsv).Write(fixation);
  saccade::LoggedDetections detections;
  if (saccade::DecodeDetections(data, size, &detections))
    saccade::DetectionWriter(out, saccade::TableFormat::kJsonl).Write(detections);
  // The viewer: every channel it listens to, then its state and preview as served.
  static saccade::ViewerState viewer{saccade::ViewerOptions{}};
  for (const char* channel :
       {"SACCADE_DETECTIONS", "SACCADE_FIXATION", "SACCADE_STATUS", "SACCADE_PREVIEW"})
    viewer.OnMessage(channel, data, size, 1.0);
  if (viewer.StateJson(1.0).empty()) __builtin_trap();
  viewer.PreviewImage(-1);
  viewer.PreviewPoints(-1);
  return 0;
}
