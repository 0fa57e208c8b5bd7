#include "daemon/args.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include "core/fail.h"

namespace saccade {

bool Args::Parse(const std::vector<std::string>& argv, const std::set<std::string>& valued,
                 const std::set<std::string>& booleans, std::string* error) {
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.rfind("--", 0) != 0) {
      return Fail(error, "unexpected argument '" + a + "'");
    }
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (booleans.count(name) && !inline_value) {
      values_[name] = "true";
    } else if (valued.count(name)) {
      if (!inline_value) {
        if (i + 1 >= argv.size()) {
          return Fail(error, "flag --" + name + " needs a value");
        }
        value = argv[++i];
      }
      values_[name] = value;
    } else {
      return Fail(error, "unknown flag --" + name);
    }
  }
  return true;
}

std::string Args::Get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
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
