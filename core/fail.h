// The one way Saccade's functions report an expected failure: a message in an optional
// out-parameter and `false` returned, so callers can write `return Fail(error, "...");`.
#pragma once

#include <cstddef>
#include <string>

namespace saccade {

/// `text` as one printable line: each control character (a newline, a tab, a NUL that came
/// from a file or a message and is echoed in an error) is written as \n, \t or \xNN.
inline std::string OneLine(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[u >> 4];
      out += hex[u & 0xf];
    }
  }
  return out;
}

/// `line` cut to at most about kMaxErrorChars: an error echoing a value it was given (a 1 MB
/// path, a 100 KB config line) keeps its head and tail and says how long the whole was.
constexpr std::size_t kMaxErrorChars = 400;
inline std::string CutLine(const std::string& line) {
  if (line.size() <= kMaxErrorChars) return line;
  const std::size_t head = kMaxErrorChars - 120, tail = 80;
  return line.substr(0, head) + " [... " + std::to_string(line.size() - head - tail) +
         " characters cut of " + std::to_string(line.size()) + " ...] " +
         line.substr(line.size() - tail);
}

/// Sets *error (when error is not null) to `message`, made one line and cut to a readable
/// length (CutLine), and returns false.
inline bool Fail(std::string* error, const std::string& message) {
  if (error) *error = CutLine(OneLine(message));
  return false;
}

}  // namespace saccade
