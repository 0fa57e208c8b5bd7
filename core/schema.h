// Each options struct names its fields once, beside their declarations, in a member template
// (Drake's Serialize pattern):
//
//   template <typename Archive>
//   void Serialize(Archive* a) {
//     a->Visit("hough_bin_m", &hough_bin_m);
//     a->Choice("growth", &growth_kind, {{"additive", GrowthKind::kAdditive}, ...});
//   }
//
// The name is the configuration key. io/config/config.h reads YAML through it, strictly; SameFields
// compares two structs through it, so equality cannot go stale when a field is added. Pure: no
// I/O here.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstring>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace saccade {

/// An enum's configuration names, in the order a message lists them.
template <typename Enum>
using ChoiceNames = std::initializer_list<std::pair<const char*, Enum>>;

/// The name of `value` among `names`, "?" when it is none of them.
template <typename Enum>
const char* ChoiceName(Enum value, ChoiceNames<Enum> names) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "?";
}

/// Collects the bytes of every field a Serialize visits.
class FingerprintArchive {
 public:
  template <typename T>
  void Visit(const char* /*name*/, T* field) {
    Add(*field);
  }
  template <typename Enum>
  void Choice(const char* /*name*/, Enum* field, ChoiceNames<Enum> /*names*/) {
    Add(*field);
  }
  template <typename Options>
  void Section(const char* /*name*/, Options* options) {
    options->Serialize(this);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  template <typename T>
  std::enable_if_t<std::is_arithmetic_v<T> || std::is_enum_v<T>> Add(const T& v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename Scalar, int Rows, int Cols, int Options, int MaxRows, int MaxCols>
  void Add(const Eigen::Matrix<Scalar, Rows, Cols, Options, MaxRows, MaxCols>& m) {
    for (Eigen::Index i = 0; i < m.size(); ++i) Add(m.data()[i]);
  }
  void Add(const Eigen::Quaternionf& q) { Add(q.coeffs()); }
  void Add(const std::string& s) {
    Add(s.size());
    bytes_ += s;
  }
  template <typename T>
  void Add(const std::vector<T>& list) {
    Add(list.size());
    for (const T& v : list) Add(v);
  }
  std::string bytes_;
};

/// True when every field `Options::Serialize` names holds the same value (bit for bit) in `a`
/// and in `b`.
template <typename Options>
bool SameFields(const Options& a, const Options& b) {
  Options ca = a, cb = b;  // Serialize takes pointers to fields it may also be asked to set
  FingerprintArchive fa, fb;
  ca.Serialize(&fa);
  cb.Serialize(&fb);
  return fa.bytes() == fb.bytes();
}

}  // namespace saccade
