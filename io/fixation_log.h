// The attention log for users: fixation_t messages as CSV or JSON lines, live from LCM
// (`saccade log-fixations`) or from an lcm-logger file (`saccade fixations`).
#pragma once

#include "core/fixation.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>

namespace saccade {

/// One fixation_t as logged: the fixation (back in core's shape) with its wire stamp and the
/// frame its positions are in ("camera", or the robot frame the daemon published in).
struct LoggedFixation {
  std::int64_t utime = 0;  // the frame's capture time, microseconds
  std::string frame;
  Fixation fixation;
};

/// Decodes one fixation_t message; false when the bytes are not one (or its mode is unknown).
bool DecodeFixation(const void* data, std::size_t size, LoggedFixation* logged);

/// Writes records as CSV (with a header line) or JSON lines, chosen by the file name.
class FixationWriter {
 public:
  enum class Format { kCsv, kJsonl };
  /// .csv or .jsonl; false with `error` for any other name.
  static bool FormatOf(const std::string& path, Format* format, std::string* error);
  FixationWriter(std::ostream& out, Format format);
  void Write(const LoggedFixation& logged);

 private:
  std::ostream& out_;
  Format format_;
};

/// What a conversion did.
struct FixationLogStats {
  std::int64_t written = 0;
  std::int64_t skipped = 0;  // messages on the channel that did not decode, corrupt events
};

/// Whether `path` is an lcm-logger log, checked before anything reads it: a regular file, not
/// empty, starting with an event's sync word. False with "PATH: reason" otherwise.
bool CheckLcmLog(const std::string& path, std::string* error);

/// Writes every message of `channel` in an lcm-logger log (CheckLcmLog first). Each event's
/// lengths are checked against the file before it is read; a corrupt stretch is skipped to the
/// next event, a truncated last event ends the log; both are counted in `stats->skipped`. False
/// with `error` when the log cannot be read.
bool ConvertFixationLog(const std::string& log_path, const std::string& channel,
                        FixationWriter* writer, FixationLogStats* stats, std::string* error);

/// Subscribes to `channel` at `url` and writes each fixation until `stop` is set (checked at
/// least every 200 ms) or `max_records` are written (0: no limit). False with `error` when LCM
/// cannot be opened.
bool ListenFixations(const std::string& url, const std::string& channel, FixationWriter* writer,
                     std::int64_t max_records, const std::atomic<bool>& stop,
                     FixationLogStats* stats, std::string* error);

}  // namespace saccade
