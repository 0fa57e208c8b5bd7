// A minimal JSON writer for the command line's --json output (no parsing, no dependencies).
#pragma once

#include <charconv>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace saccade {

/// Builds one JSON value left to right; the caller keeps keys and values paired.
class JsonWriter {
 public:
  JsonWriter& BeginObject() { return Open('{'); }
  JsonWriter& EndObject() { return Close('}'); }
  JsonWriter& BeginArray() { return Open('['); }
  JsonWriter& EndArray() { return Close(']'); }
  JsonWriter& Key(const std::string& k) {
    Separate();
    String(k);
    out_ << ':';
    after_key_ = true;
    return *this;
  }
  JsonWriter& Value(double v) {
    Separate();
    if (std::isfinite(v))
      out_ << std::setprecision(9) << v;
    else
      out_ << "null";
    return *this;
  }
  /// A float at the precision it has: its shortest text that reads back as the same float.
  JsonWriter& Value(float v) {
    Separate();
    char text[32];
    if (std::isfinite(v))
      out_.write(text, std::to_chars(text, text + sizeof text, v).ptr - text);
    else
      out_ << "null";
    return *this;
  }
  JsonWriter& Value(int v) { return Value(static_cast<long long>(v)); }
  JsonWriter& Value(long long v) {
    Separate();
    out_ << v;
    return *this;
  }
  JsonWriter& Value(std::size_t v) { return Value(static_cast<long long>(v)); }
  JsonWriter& Value(bool v) {
    Separate();
    out_ << (v ? "true" : "false");
    return *this;
  }
  JsonWriter& Value(const std::string& v) {
    Separate();
    String(v);
    return *this;
  }
  /// [x, y, z] of any 3-vector indexable with [] (an Eigen vector, a std::array).
  template <typename Vector>
  JsonWriter& Vector3(const Vector& v) {
    return BeginArray().Value(double(v[0])).Value(double(v[1])).Value(double(v[2])).EndArray();
  }
  JsonWriter& Null() {
    Separate();
    out_ << "null";
    return *this;
  }
  std::string str() const { return out_.str(); }

 private:
  JsonWriter& Open(char c) {
    Separate();
    out_ << c;
    first_ = true;
    return *this;
  }
  JsonWriter& Close(char c) {
    out_ << c;
    first_ = false;
    return *this;
  }
  void Separate() {
    if (after_key_) {
      after_key_ = false;
      return;
    }
    if (!first_) out_ << ',';
    first_ = false;
  }
  void String(const std::string& s) {
    out_ << '"';
    for (char c : s) {
      switch (c) {
        case '"':
          out_ << "\\\"";
          break;
        case '\\':
          out_ << "\\\\";
          break;
        case '\n':
          out_ << "\\n";
          break;
        case '\t':
          out_ << "\\t";
          break;
        default:
          if (static_cast<unsigned char>(c) < 0x20)
            out_ << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec;
          else
            out_ << c;
      }
    }
    out_ << '"';
  }
  std::ostringstream out_;
  bool first_ = true;
  bool after_key_ = false;
};

}  // namespace saccade
