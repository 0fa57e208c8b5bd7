#include "daemon/args.h"

#include "daemon/exit_codes.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <ostream>
#include <sstream>
#include <utility>

namespace saccade {
namespace {

// Levenshtein distance, for "did you mean".
std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The flag's name in `token` ("--fovea=1,2,3" -> "fovea"); empty when it is not a long flag.
std::string FlagName(const std::string& token) {
  if (token.rfind("--", 0) != 0 || token.size() == 2) return "";
  return token.substr(2, token.find('=') - 2);
}

// `text` broken into lines of at most 79 columns at spaces: the first line starts at column
// `first` (the caller has filled it), the others are indented to `indent`. Ends with a newline.
std::string Wrap(const std::string& text, std::size_t first, std::size_t indent) {
  constexpr std::size_t kWidth = 79;
  std::istringstream words(text);
  std::string out, word;
  std::size_t column = first;
  bool line_empty = true;
  while (words >> word) {
    if (!line_empty && column + 1 + word.size() > kWidth) {
      out += "\n" + std::string(indent, ' ');
      column = indent;
      line_empty = true;
    }
    if (!line_empty) out += ' ', ++column;
    out += word;
    column += word.size();
    line_empty = false;
  }
  return out + "\n";
}

}  // namespace

Args::Args(std::string program, std::string about)
    : program_(std::move(program)), about_(std::move(about)) {}

Args& Args::Value(const std::string& name, const std::string& value, const std::string& help) {
  specs_.push_back({name, value, help, false});
  return *this;
}

Args& Args::Switch(const std::string& name, const std::string& help) {
  specs_.push_back({name, "", help, false});
  return *this;
}

Args& Args::Positional(const std::string& name, const std::string& help) {
  specs_.push_back({name, name, help, true});
  return *this;
}

Args& Args::Footer(const std::string& text) {
  footer_ = text;
  return *this;
}

namespace {

// The declared flags as one CLI11 app, with -h/--help and --version as every command has them.
// Each value lands in `strings` (a switch in `switches`); `options` tells which were given.
struct Parser {
  CLI::App app;
  std::map<std::string, std::string> strings;
  std::map<std::string, bool> switches;
  std::map<std::string, CLI::Option*> options;

  Parser(const std::string& program, const std::vector<Args::Spec>& specs) : app("", program) {
    app.set_help_flag("-h,--help", "print this help and exit");
    app.set_version_flag("--version", std::string(),
                         "print the version and the libraries' versions and exit");
    for (const Args::Spec& s : specs) {
      if (s.positional) {
        options[s.name] = app.add_option(s.name, strings[s.name], s.help)->type_name("");
      } else if (s.value.empty()) {
        options[s.name] = app.add_flag("--" + s.name, switches[s.name], s.help);
      } else {
        options[s.name] = app.add_option("--" + s.name, strings[s.name], s.help)
                              ->type_name(s.value)
                              ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
      }
    }
  }
};

}  // namespace

std::string Args::Help() const {
  std::ostringstream help;
  help << "usage: " << program_;
  for (const Spec& s : specs_)
    if (s.positional) help << " " << s.name;
  help << " [flags]\n\n" << Wrap(about_, 0, 0);
  const auto entry = [&help](const std::string& left, const std::string& text) {
    const std::string head = "  " + left;
    constexpr std::size_t kColumn = 28;
    help << head;
    if (head.size() + 1 > kColumn)
      help << "\n" << std::string(kColumn, ' ');
    else
      help << std::string(kColumn - head.size(), ' ');
    help << Wrap(text, kColumn, kColumn);
  };
  bool any_positional = false;
  for (const Spec& s : specs_) {
    if (!s.positional) continue;
    if (!any_positional) help << "\narguments:\n";
    any_positional = true;
    entry(s.name, s.help);
  }
  help << "\nflags:\n";
  for (const Spec& s : specs_)
    if (!s.positional) entry("--" + s.name + (s.value.empty() ? "" : " " + s.value), s.help);
  entry("-h, --help", "print this help and exit");
  entry("--version", "print the version and the libraries' versions and exit");
  if (!footer_.empty()) help << "\n" << footer_ << "\n";
  return help.str();
}

std::string Args::Check(const std::vector<std::string>& argv) const {
  std::vector<std::string> known{"help", "version"};
  std::size_t positionals = 0;
  for (const Spec& s : specs_) {
    if (s.positional)
      ++positionals;
    else
      known.push_back(s.name);
  }
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a == "-h") continue;  // --help's short form, which CLI11 answers
    const std::string name = FlagName(a);
    const bool inline_value = a.find('=') != std::string::npos;
    if (!name.empty()) {
      const auto spec = std::find_if(specs_.begin(), specs_.end(), [&](const Spec& s) {
        return !s.positional && s.name == name;
      });
      if (spec == specs_.end()) {
        if (name == "help" || name == "version") continue;
        const std::string near = Nearest(name, known);
        return "unknown flag --" + name + (near.empty() ? "" : " (did you mean --" + near + "?)");
      }
      if (spec->value.empty() && inline_value) return "flag --" + name + " takes no value";
      if (!spec->value.empty() && inline_value && a.back() == '=')  // CLI11 would take the next
        return "flag --" + name + " needs a value (" + spec->value + ")";
      if (!spec->value.empty() && !inline_value) {
        // A value that starts with "--" is given as --name=--value.
        if (i + 1 == argv.size() || !FlagName(argv[i + 1]).empty())
          return "flag --" + name + " needs a value (" + spec->value + ")";
        ++i;
      }
    } else if (a.size() > 1 && a[0] == '-' && !ParseNumber(a)) {
      return "unknown flag " + a;
    } else if (positionals == 0) {
      return "unexpected argument '" + a + "'";
    } else {
      --positionals;
    }
  }
  return "";
}

std::optional<int> Args::Parse(const std::vector<std::string>& argv, std::ostream& out,
                               std::ostream& err) {
  Parser parser(program_, specs_);
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());
  const auto fail = [&](const std::string& message) -> std::optional<int> {
    err << program_ << ": " << message << " (see " << program_ << " --help)\n";
    return kExitUsage;
  };
  // CLI11 would take a flag after a flag that needs a value as that value, and its messages name
  // its own terms: the arguments are checked here first, and CLI11 parses what passed.
  const std::string wrong = Check(argv);
  if (!wrong.empty()) return fail(wrong);
  try {
    parser.app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    out << Help();
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    out << VersionText(program_.substr(0, program_.find(' '))) << "\n";  // the program
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    return fail(e.what());
  }
  for (const auto& [name, option] : parser.options) {
    if (option->count() == 0) continue;
    const auto on = parser.switches.find(name);
    if (on == parser.switches.end())
      values_[name] = parser.strings[name];
    else if (on->second)
      values_[name] = "true";
  }
  return std::nullopt;
}

std::string Args::Get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

std::string Args::Nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string& c : candidates) {
    const std::size_t d = EditDistance(word, c);
    if (d < best_distance) best_distance = d, best = c;
  }
  // A third of the word may be wrong (at least 2 letters, so "fovae" finds "fovea").
  const std::size_t tolerance = std::max<std::size_t>(2, word.size() / 3);
  return best_distance <= tolerance ? best : "";
}

std::string Args::Default(double value) {
  std::ostringstream text;
  text << " (default: " << value << ")";
  return text.str();
}

std::vector<std::string> Args::ParseList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) out.push_back(item);
  return out;
}

std::optional<Eigen::Vector3f> Args::ParseVector3(const std::string& text) {
  Eigen::Vector3f v;
  std::stringstream s(text);
  std::string part;
  int n = 0;
  while (std::getline(s, part, ',')) {
    if (n == 3) return std::nullopt;
    const auto d = ParseNumber(part);
    // Finite as a float too: 1e39 would become infinity.
    if (!d || std::abs(*d) > std::numeric_limits<float>::max()) return std::nullopt;
    v[n++] = static_cast<float>(*d);
  }
  if (n != 3) return std::nullopt;
  return v;
}

std::optional<double> Args::ParseNumber(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> Args::ParsePositiveInt(const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < 1 || v > 1000000) return std::nullopt;
  return static_cast<int>(v);
}

}  // namespace saccade
