// Signed commands (docs/LCM.md, "Signed commands"): the command key, the HMAC-SHA256 that signs
// an encoded command_t, and the check saccaded makes before it reads anything else of one.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace saccade {

/// Where saccaded looks for the command key unless `lcm.command_key` says otherwise.
inline constexpr const char* kDefaultCommandKeyPath = "/etc/saccade/command.key";

using Digest = std::array<std::uint8_t, 32>;

/// The signature: command_t's last field, its last 32 bytes on the wire.
inline constexpr std::size_t kCommandSignatureBytes = 32;

/// HMAC-SHA256 of `size` bytes with `key` (OpenSSL's).
Digest HmacSha256(const Digest& key, const void* data, std::size_t size);

/// Writes a new random key (OpenSSL's RAND_bytes) to `path` as 64 hexadecimal digits and a
/// newline, mode 0600, made beside it and renamed into place (its folder is made when missing).
/// `owner` (a user name, or empty) is given the file. Refuses to replace a key unless `force`.
/// False with one line naming the path on failure.
bool WriteCommandKey(const std::string& path, const std::string& owner, bool force,
                     std::string* error);

/// Reads a key WriteCommandKey wrote. Refused: not a regular file, readable or writable by
/// group or others (a key others can read signs for them too), not 64 hexadecimal digits.
bool ReadCommandKey(const std::string& path, Digest* key, std::string* error);

/// Signs an encoded command_t in place: its last 32 bytes (the signature field) become the
/// HMAC of every byte before them. `encoded` must be at least 33 bytes.
void SignCommand(const Digest& key, std::vector<std::uint8_t>* encoded);

/// The gate a signed command passes before it is decoded: its signature, then its age, then
/// whether it was seen before. Not thread-safe (the bus's one receiving thread calls it).
class CommandGate {
 public:
  /// `now_utime` gives the daemon's wall clock in microseconds since the epoch.
  CommandGate(const Digest& key, double max_age_s, std::function<std::int64_t()> now_utime);

  /// True when `data` is a command_t signed with the key, sent within max_age_s of now (either
  /// way: the sender's clock may run ahead), and not accepted before (the same bytes, so the
  /// same signature; a sender tells two alike commands apart by their utime or sequence).
  /// Else false with one line: unsigned, a wrong signature, too old, a replay.
  bool Admit(const void* data, std::size_t size, std::string* why);

  /// At most this many signed commands are remembered within max_age_s; beyond, one is refused.
  static constexpr std::size_t kMaxRemembered = 65536;

 private:
  Digest key_;
  std::int64_t max_age_us_;
  std::function<std::int64_t()> now_;
  std::set<std::pair<std::int64_t, Digest>> seen_;  // (utime, signature), oldest first
};

}  // namespace saccade
