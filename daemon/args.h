// Command lines of `saccade`'s subcommands and of `saccaded`: `--name value`, `--name=value`,
// boolean `--name` and positional arguments, each declared with its help (what it is, its unit
// and its default), so that `--help` lists every flag and a mistyped one gets "did you mean".
// The parsing itself is CLI11's, kept in args.cc.
#pragma once

#include <Eigen/Core>

#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

class Args {
 public:
  /// `program` names the command in its help and its errors ("saccade recognize");
  /// `about` says what it does, for its help.
  Args(std::string program, std::string about);

  /// A flag with a value, `--name VALUE`. `help` says what it is and in which unit, and its
  /// default when it has one ("default: 1"); the command checks the value itself.
  Args& Value(const std::string& name, const std::string& value, const std::string& help);
  /// A flag that stands alone, `--name`.
  Args& Switch(const std::string& name, const std::string& help);
  /// A positional argument, in declaration order; the command checks that it is there.
  Args& Positional(const std::string& name, const std::string& help);
  /// Text after the flags in the help (exit codes, examples).
  Args& Footer(const std::string& text);

  /// Parses `argv` (the arguments after the command). Returns the exit code when the command
  /// must not go on: 0 after `--help` or `--version` was printed to `out`, 2 after a usage error
  /// was printed to `err` as one line ("saccade recognize: unknown flag --fovae (did you mean
  /// --fovea?)"). A flag given twice keeps its last value.
  std::optional<int> Parse(const std::vector<std::string>& argv, std::ostream& out,
                           std::ostream& err);

  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  /// The help `--help` prints.
  std::string Help() const;

  /// "x,y,z" as three finite numbers.
  static std::optional<Eigen::Vector3f> ParseVector3(const std::string& text);
  /// One finite number, nothing else.
  static std::optional<double> ParseNumber(const std::string& text);
  /// A whole positive integer.
  static std::optional<int> ParsePositiveInt(const std::string& text);
  /// " (default: V)" for a help text, V as the code's own default prints (1.5, 0.01).
  static std::string Default(double value);
  /// "a,b,c" as its comma-separated items; empty for an empty text.
  static std::vector<std::string> ParseList(const std::string& text);
  /// The one of `candidates` closest to `word` by edit distance, when it is close enough to be
  /// a likely typo; empty otherwise.
  static std::string Nearest(const std::string& word, const std::vector<std::string>& candidates);

  /// One declared flag or positional argument.
  struct Spec {
    std::string name;
    std::string value;  // what its value looks like ("M.pcd"); empty: a switch
    std::string help;
    bool positional = false;
  };

 private:
  /// What is wrong with `argv` (an unknown flag, a missing value, a stray argument), in one
  /// phrase; empty when nothing is.
  std::string Check(const std::vector<std::string>& argv) const;

  std::string program_, about_, footer_;
  std::vector<Spec> specs_;
  std::map<std::string, std::string> values_;
};

/// What `--version` prints: Saccade's version and git commit, and the versions of the libraries
/// it was built with (PCL, OpenNI2, LCM, TBB, Eigen).
std::string VersionText(const std::string& program);

}  // namespace saccade
