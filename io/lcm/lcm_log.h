// Reading what saccaded published: lcm-logger files, checked event by event, and the guarded
// decoding of a message's wire layout (lcm-gen's decoders trust a string's length).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>

#include "io/base/text.h"  // CsvField, ShortestFloat: what the log writers print with

namespace saccade {

/// What a conversion did.
struct LcmLogStats {
  std::int64_t written = 0;
  std::int64_t skipped = 0;  // messages on the channel that did not decode, corrupt events
};

/// The formats the log converters write: CSV (a header line naming each column with its unit)
/// or JSON lines.
enum class TableFormat { kCsv, kJsonl };
/// Chosen by the output's name: .csv or .jsonl; false with `error` for any other.
bool TableFormatOf(const std::string& path, TableFormat* format, std::string* error);

/// Whether `path` is an lcm-logger log, checked before anything reads it: a regular file, not
/// empty, starting with an event's sync word. False with "PATH: reason" otherwise.
bool CheckLcmLog(const std::string& path, std::string* error);

/// Calls `message` with the data of every event of `channel` in an lcm-logger log (CheckLcmLog
/// first); it returns whether the data decoded (counted as written, else skipped). Each event's
/// lengths are checked against the file before it is read; a corrupt stretch is skipped to the
/// next event, a truncated last event ends the log; both are counted in `stats->skipped`.
/// False with `error` when the log cannot be read.
bool ReadLcmLog(const std::string& path, const std::string& channel,
                const std::function<bool(const unsigned char* data, std::size_t size)>& message,
                LcmLogStats* stats, std::string* error);

/// One event of an lcm-logger log: its channel, when the logger received it (microseconds since
/// the epoch) and its data.
struct LcmLogEvent {
  const std::string& channel;
  std::int64_t utime;
  const unsigned char* data;
  std::size_t size;
};

/// As ReadLcmLog, for every event whose channel is `wanted`, in the log's order.
bool ReadLcmLogEvents(const std::string& path,
                      const std::function<bool(const std::string& channel)>& wanted,
                      const std::function<bool(const LcmLogEvent& event)>& message,
                      LcmLogStats* stats, std::string* error);

/// A message's fields as lcm-gen encodes them: each one's size in bytes, or kLcmString for a
/// string (a big-endian int32 length counting its final NUL, then the bytes).
constexpr int kLcmString = -1;

/// Walks `layout` from `*at` in `data[0, size)`: true, with `*at` past the fields, when every
/// field is within the message and every string's length is at least 1 and within it (a
/// length of 0 or below would make lcm-gen's decoder copy (size_t)-1 bytes).
bool LcmFieldsFit(const unsigned char* data, std::size_t size, std::size_t* at,
                  std::initializer_list<int> layout);

/// The big-endian int32 at `p`, as LCM writes integers.
std::int32_t LcmInt32(const unsigned char* p);

}  // namespace saccade
