// Command-line flags of the `saccade` subcommands: `--name value` and boolean `--name`.
#pragma once

#include <Eigen/Core>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace saccade {

class Args {
 public:
  /// Parses `argv`; `valued` flags take the next argument, `booleans` stand alone. False with
  /// `error` on an unknown flag, a missing value or a stray argument.
  bool Parse(const std::vector<std::string>& argv, const std::set<std::string>& valued,
             const std::set<std::string>& booleans, std::string* error);
  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  /// "x,y,z" as three finite numbers.
  static std::optional<Eigen::Vector3f> ParseVector3(const std::string& text);
  /// One finite number, nothing else.
  static std::optional<double> ParseNumber(const std::string& text);
  /// A whole positive integer.
  static std::optional<int> ParsePositiveInt(const std::string& text);
  /// "a,b,c" as its comma-separated items; empty for an empty text.
  static std::vector<std::string> ParseList(const std::string& text);

 private:
  std::map<std::string, std::string> values_;
};

}  // namespace saccade
