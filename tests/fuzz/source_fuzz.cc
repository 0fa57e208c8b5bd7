// libFuzzer target: source specs (`--source`, `source:`) on arbitrary text. Each is parsed
// and, unless it names a device (openni2://, freenect://, which would wait for one), opened:
// every option is checked there, and a path that is not there must be one line. A spec that
// opens is closed again without reading a frame.
#include "io/sources/frame_source.h"
#include "tests/fuzz/fuzz_file.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace saccade;
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const auto spec = ParseSourceSpec(text, &error);
  fuzz::CheckRefusal(spec.has_value(), error);
  if (!spec || spec->kind == "openni2" || spec->kind == "freenect") return 0;
  // Only paths that cannot exist: the fuzzer must not wander the file system.
  if (spec->kind != "synthetic" && spec->target.rfind("/nonexistent/", 0) != 0) return 0;
  if (spec->kind == "synthetic" && spec->target.find('/') != std::string::npos) return 0;
  error.clear();
  const auto source = OpenSource(text, &error, 0.0);
  fuzz::CheckRefusal(source != nullptr, error);
  return 0;
}
