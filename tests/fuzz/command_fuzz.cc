// libFuzzer target: the command decoder (DecodeCommand in io/bus.h) on arbitrary bytes, which
// is what the LCM command channel delivers. It must return a command or one line, never crash.
#include "io/bus.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string why;
  const auto command = saccade::DecodeCommand(data, size, saccade::BusOptions{},
                                              Eigen::Isometry3f::Identity(), &why);
  if (!command && (why.empty() || why.find('\n') != std::string::npos)) __builtin_trap();
  return 0;
}
