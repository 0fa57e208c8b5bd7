// libFuzzer target: the PCD check (io/formats/pcd_check.h) on arbitrary bytes. It must return, true
// or false with one line, and never read or write out of bounds (build with ASan and UBSan).
#include "io/formats/pcd_check.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  saccade::PcdHeader header;
  std::string error;
  const bool ok = saccade::CheckPcdBytes(
      "fuzz.pcd", std::string(reinterpret_cast<const char*>(data), size), &header, &error);
  if (!ok && (error.empty() || error.find('\n') != std::string::npos)) __builtin_trap();
  return 0;
}
