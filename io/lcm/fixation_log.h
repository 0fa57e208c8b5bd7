// The attention log for users: fixation_t messages as CSV or JSON lines, live from LCM
// (`saccade log-fixations`) or from an lcm-logger file (`saccade fixations`).
#pragma once

#include "core/fixation.h"
#include "io/lcm/lcm_log.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>

namespace lcm {
class LCM;
}

namespace saccade {

/// One fixation_t as logged: the fixation (back in core's shape) with its wire stamp and the
/// frame its positions are in ("camera", or the robot frame the daemon published in).
struct LoggedFixation {
  std::int64_t utime = 0;         // when the frame reached the host, epoch microseconds
  std::int64_t sensor_utime = 0;  // its capture time on the sensor's clock, microseconds
  std::string frame;
  Fixation fixation;
};

/// Decodes one fixation_t message; false when the bytes are not one (or its mode is unknown).
bool DecodeFixation(const void* data, std::size_t size, LoggedFixation* logged);

/// Writes records as CSV (a header line with each column's unit) or JSON lines, chosen by the
/// file name; numbers at the precision they have.
class FixationWriter {
 public:
  using Format = TableFormat;
  /// .csv or .jsonl; false with `error` for any other name.
  static bool FormatOf(const std::string& path, Format* format, std::string* error);
  FixationWriter(std::ostream& out, Format format);
  void Write(const LoggedFixation& logged);

 private:
  std::ostream& out_;
  Format format_;
};

/// Writes every fixation of `channel` in an lcm-logger log (ReadLcmLog: checked event by event).
bool ConvertFixationLog(const std::string& log_path, const std::string& channel,
                        FixationWriter* writer, LcmLogStats* stats, std::string* error);

/// Subscribes to `channel` on `lcm` (OpenLcm, io/lcm/lcm_open.h) and writes each fixation until
/// `stop` is set (checked at least every 200 ms), `max_records` are written (0: no limit), or
/// `flushed`, called after each fixation written, returns false (its output failed).
void ListenFixations(lcm::LCM* lcm, const std::string& channel, FixationWriter* writer,
                     std::int64_t max_records, const std::atomic<bool>& stop, LcmLogStats* stats,
                     const std::function<bool()>& flushed);

}  // namespace saccade
