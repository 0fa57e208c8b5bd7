#include "io/formats/output_file.h"

#include "core/fail.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace saccade {

namespace {

std::string CannotWrite(const std::string& path, int why) {
  return path + ": cannot write it (" + (why != 0 ? std::strerror(why) : "write failed") + ")";
}

// Writes all of `bytes` to `fd`, across short writes; the errno of a failure, else 0.
int WriteAll(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : ENOSPC;
    done += static_cast<std::size_t>(n);
  }
  return 0;
}

}  // namespace

bool WriteBytes(const std::string& path, const std::string& bytes, std::string* error) {
  const std::string part = path + ".part";
  const int fd = open(part.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Fail(error, CannotWrite(path, errno));
  int why = WriteAll(fd, bytes);
  // Data a full disk refused can surface at close only (NFS); no fsync: a recording writes
  // thirty files a second.
  if (close(fd) != 0 && why == 0) why = errno;
  if (why == 0 && std::rename(part.c_str(), path.c_str()) != 0) why = errno;
  if (why != 0) {
    unlink(part.c_str());
    return Fail(error, CannotWrite(path, why));
  }
  return true;
}

RecordFile::~RecordFile() {
  if (fd_ >= 0) close(fd_);
}

bool RecordFile::Open(const std::string& path, std::string* error) {
  path_ = path;
  size_ = 0;
  fd_ = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) return Fail(error, CannotWrite(path, errno));
  return true;
}

bool RecordFile::Append(const std::string& bytes, std::string* error) {
  if (fd_ < 0) return Fail(error, CannotWrite(path_, EBADF));
  const int why = WriteAll(fd_, bytes);
  if (why != 0) {
    // The part of the record that went in comes out again: the file ends on a whole record.
    if (ftruncate(fd_, static_cast<off_t>(size_)) == 0)
      lseek(fd_, static_cast<off_t>(size_), SEEK_SET);
    return Fail(error, CannotWrite(path_, why));
  }
  size_ += bytes.size();
  return true;
}

bool RecordFile::Close(std::string* error) {
  if (fd_ < 0) return true;
  int why = 0;
  if (fsync(fd_) != 0 && errno != EINVAL) why = errno;
  if (close(fd_) != 0 && why == 0) why = errno;
  fd_ = -1;
  if (why != 0) return Fail(error, CannotWrite(path_, why));
  return true;
}

}  // namespace saccade
