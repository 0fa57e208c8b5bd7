#include "io/lcm/command_key.h"

#include "core/fail.h"

#include <fcntl.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/rand.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace saccade {

namespace {

// command_t's layout (io/lcm/lcmtypes/command_t.lcm): the type's 8-byte hash, utime and sequence
// (big-endian int64 each), ..., the 32-byte signature last.
constexpr std::size_t kUtimeOffset = 8, kSequenceOffset = 16;
constexpr std::size_t kSignatureBytes = kCommandSignatureBytes;
constexpr std::size_t kMinSignedBytes = kSequenceOffset + 8 + kSignatureBytes;

std::int64_t BigEndian64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}

std::string Errno() { return std::strerror(errno); }

}  // namespace

Digest HmacSha256(const Digest& key, const void* data, std::size_t size) {
  Digest out{};
  unsigned int length = 0;
  HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()),
       static_cast<const unsigned char*>(data), size, out.data(), &length);
  return out;
}

bool WriteCommandKey(const std::string& path, const std::string& owner, bool force,
                     std::string* error) {
  struct stat st {};
  if (!force && lstat(path.c_str(), &st) == 0)
    return Fail(error, path +
                           ": a key is already there (--force replaces it; every sender "
                           "then needs the new one)");
  uid_t uid = static_cast<uid_t>(-1);
  gid_t gid = static_cast<gid_t>(-1);
  if (!owner.empty()) {
    const passwd* user = getpwnam(owner.c_str());
    if (!user) return Fail(error, "no such user '" + owner + "'");
    uid = user->pw_uid, gid = user->pw_gid;
  }
  Digest key{};
  if (RAND_bytes(key.data(), static_cast<int>(key.size())) != 1)
    return Fail(error, "OpenSSL could not make random bytes for a key");
  std::string text;
  char hex[3];
  for (const std::uint8_t b : key) {
    std::snprintf(hex, sizeof hex, "%02x", b);
    text += hex;
  }
  text += "\n";

  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty()) std::filesystem::create_directories(folder, ec);
  if (ec) return Fail(error, folder.string() + ": cannot make the folder (" + ec.message() + ")");
  const std::string part = path + ".part";
  unlink(part.c_str());
  const int fd = open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return Fail(error, part + ": cannot create it (" + Errno() + ")");
  const bool written = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
                       (owner.empty() || fchown(fd, uid, gid) == 0) && fchmod(fd, 0600) == 0 &&
                       fsync(fd) == 0;
  const std::string why = Errno();
  if (close(fd) != 0 || !written) {
    unlink(part.c_str());
    return Fail(error, path + ": cannot write it (" + why + ")");
  }
  if (rename(part.c_str(), path.c_str()) != 0) {
    const std::string reason = Errno();
    unlink(part.c_str());
    return Fail(error, path + ": cannot write it (" + reason + ")");
  }
  return true;
}

bool ReadCommandKey(const std::string& path, Digest* key, std::string* error) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return Fail(error, path + ": " + Errno());
  if (!S_ISREG(st.st_mode)) return Fail(error, path + ": not a regular file, not a command key");
  if (st.st_mode & 077) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    return Fail(error, path + ": the command key is open to others (mode " + mode +
                           "): chmod 600 it, and make a new one if others read it");
  }
  std::ifstream in(path);
  if (!in) return Fail(error, path + ": " + Errno());
  std::string text;
  std::getline(in, text, '\0');
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  const auto digit = [](char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  bool hex = text.size() == 2 * key->size();
  for (std::size_t i = 0; hex && i < key->size(); ++i) {
    const int hi = digit(text[2 * i]), lo = digit(text[2 * i + 1]);
    hex = hi >= 0 && lo >= 0;
    (*key)[i] = static_cast<std::uint8_t>(hi * 16 + lo);
  }
  if (!hex)
    return Fail(error, path +
                           ": not a command key (64 hexadecimal digits, as saccade keygen "
                           "writes)");
  return true;
}

void SignCommand(const Digest& key, std::vector<std::uint8_t>* encoded) {
  const std::size_t body = encoded->size() - kSignatureBytes;
  const Digest mac = HmacSha256(key, encoded->data(), body);
  std::memcpy(encoded->data() + body, mac.data(), mac.size());
}

CommandGate::CommandGate(const Digest& key, double max_age_s,
                         std::function<std::int64_t()> now_utime)
    : key_(key),
      max_age_us_(static_cast<std::int64_t>(max_age_s * 1e6)),
      now_(std::move(now_utime)) {}

bool CommandGate::Admit(const void* data, std::size_t size, std::string* why) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  if (size < kMinSignedBytes) return Fail(why, "unsigned (too short to carry a signature)");
  const std::size_t body = size - kSignatureBytes;
  const Digest mac = HmacSha256(key_, bytes, body);
  if (CRYPTO_memcmp(mac.data(), bytes + body, mac.size()) != 0) {
    bool zeros = true;
    for (std::size_t i = body; i < size; ++i) zeros = zeros && bytes[i] == 0;
    return Fail(why, zeros ? "unsigned (commands must be signed: docs/LCM.md)"
                           : "a wrong signature (another key, or a changed message)");
  }
  const std::int64_t utime = BigEndian64(bytes + kUtimeOffset);
  const std::int64_t now = now_();
  // Forget what is too old to be admitted again anyway.
  while (!seen_.empty() && seen_.begin()->first < now - max_age_us_) seen_.erase(seen_.begin());
  const double age_s = (static_cast<double>(now) - static_cast<double>(utime)) * 1e-6;
  if (std::abs(age_s) * 1e6 > static_cast<double>(max_age_us_)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "%s %.1f s %s, beyond lcm.command_max_age_s (%.1f s): a replay, or clocks "
                  "that disagree",
                  age_s >= 0 ? "sent" : "stamped", std::abs(age_s),
                  age_s >= 0 ? "ago" : "ahead of the daemon's clock", max_age_us_ * 1e-6);
    return Fail(why, text);
  }
  if (seen_.count({utime, mac}))
    return Fail(why, "a replay (this signed command was acted on already)");
  if (seen_.size() >= kMaxRemembered)
    return Fail(why, "more than " + std::to_string(kMaxRemembered) +
                         " signed commands within lcm.command_max_age_s");
  seen_.insert({utime, mac});
  return true;
}

}  // namespace saccade
