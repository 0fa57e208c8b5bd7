// libFuzzer target: the decoders of what arrives over LCM, on arbitrary bytes: the command
// decoder (DecodeCommand in io/bus.h, what the command channel delivers to the daemon), and
// the fixation and detections decoders the log converters use (io/fixation_log.h,
// io/detections_log.h). Each must return a message or refuse, never crash.
#include "io/bus.h"
#include "io/detections_log.h"
#include "io/fixation_log.h"

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
  return 0;
}
