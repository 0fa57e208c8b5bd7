// libFuzzer target: every YAML and text loader on arbitrary bytes. The first byte picks the
// loader (the daemon's configuration, a recognition configuration, an evaluation's
// configurations, a cases file, a scenario, a capture sequence, an intrinsics file, a colour
// camera file, a truth file, an lcm-logger log of fixations); the rest is the file. Each must
// load or refuse with one line.
#include "daemon/settings.h"
#include "io/config/config.h"
#include "io/formats/images.h"
#include "io/formats/truth_file.h"
#include "io/lcm/fixation_log.h"
#include "tests/fuzz/fuzz_file.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace saccade;
  if (size == 0) return 0;
  const int which = data[0] % 10;
  const std::string path = fuzz::WriteInput(data + 1, size - 1,
                                            which == 8   ? "csv"
                                            : which == 9 ? "lcmlog"
                                                         : "yaml");
  std::string error;
  bool ok = false;
  switch (which) {
    case 0: {
      DaemonSettings settings;
      ok = LoadDaemonSettings(path, &settings, &error);
      break;
    }
    case 1: {
      RecognitionConfig config;
      ok = LoadRecognitionConfig(path, &config, &error);
      break;
    }
    case 2: {
      std::vector<EvalConfiguration> configurations;
      ok = LoadEvalConfigurations(path, RecognitionConfig{}, &configurations, &error);
      break;
    }
    case 3: {
      std::vector<LabelledCase> cases;
      ok = LoadLabelledCases(path, "/nonexistent", &cases, &error);
      break;
    }
    case 4: {
      Scenario scenario;
      ok = LoadScenario(path, &scenario, &error);
      break;
    }
    case 5: {
      CaptureSequence sequence;
      ok = LoadCaptureSequence(path, &sequence, &error);
      break;
    }
    case 6: {
      IntrinsicsFile intrinsics;
      ok = ReadIntrinsicsFile(path, &intrinsics, &error);
      break;
    }
    case 7: {
      ColourCameraFile colour;
      ok = ReadColourCameraFile(path, &colour, &error);
      break;
    }
    case 8: {
      std::vector<TruthRow> rows;
      ok = ReadTruthFile(path, &rows, &error);
      break;
    }
    default: {
      std::ostringstream out;
      FixationWriter writer(out, FixationWriter::Format::kJsonl);
      LcmLogStats stats;
      ok = ConvertFixationLog(path, "SACCADE_FIXATION", &writer, &stats, &error);
      break;
    }
  }
  fuzz::CheckRefusal(ok, error);
  return 0;
}
