// libFuzzer target: the depth and colour image readers on arbitrary bytes, as a PNG or as a
// TIFF (the first byte picks which, and whether depth or colour is read). Each must read the
// image or refuse it with one line, and never allocate what a lying header claims.
#include "io/formats/images.h"
#include "tests/fuzz/fuzz_file.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace saccade;
  if (size == 0) return 0;
  const int which = data[0] % 4;
  const std::string path = fuzz::WriteInput(data + 1, size - 1, which % 2 ? "tiff" : "png");
  std::string error;
  bool ok = false;
  if (which < 2) {
    DepthImage depth;
    ok = ReadDepthImage(path, &depth, &error);
  } else {
    RgbImage rgb;
    ok = ReadRgbImage(path, &rgb, &error);
  }
  fuzz::CheckRefusal(ok, error);
  return 0;
}
