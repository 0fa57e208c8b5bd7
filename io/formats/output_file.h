// Files Saccade writes, whole or not at all: a full disk, a short write or a failed close is an
// error naming the file and why, and never leaves a half-written file under the final name.
#pragma once

#include <cstdint>
#include <sstream>
#include <string>
#include <utility>

namespace saccade {

/// Writes `bytes` to `path` whole or not at all: beside it (PATH.part), then renamed into it, so
/// that a full disk or a failed write leaves no half file where a reader would take it for a
/// whole one; false with "PATH: cannot write it (reason)".
bool WriteBytes(const std::string& path, const std::string& bytes, std::string* error);

/// Text composed in memory, then written whole by Commit (WriteBytes); one never committed
/// writes nothing.
class TextFile : public std::ostringstream {
 public:
  explicit TextFile(std::string path) : path_(std::move(path)) {}
  bool Commit(std::string* error) const { return WriteBytes(path_, str(), error); }

 private:
  std::string path_;
};

/// A file written record by record where it lies (a live log, a dump's index): each Append is
/// written whole or cut back to the record before it, so the file always ends on a whole record,
/// and nothing appended before a failure is lost.
class RecordFile {
 public:
  RecordFile() = default;
  RecordFile(const RecordFile&) = delete;
  RecordFile& operator=(const RecordFile&) = delete;
  ~RecordFile();

  /// Creates (or empties) `path`; false with "PATH: cannot write it (reason)".
  bool Open(const std::string& path, std::string* error);
  /// Appends `bytes` whole; false, with the file cut back to its size before, and one line.
  bool Append(const std::string& bytes, std::string* error);
  /// Closes it; false when the close fails (the system could not store what was written).
  bool Close(std::string* error);
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;  // bytes of whole records
};

}  // namespace saccade
