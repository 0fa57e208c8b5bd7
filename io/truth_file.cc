#include "io/truth_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include "core/fail.h"
#include "io/text.h"

namespace saccade {

std::string TruthCsvHeader() {
  return "sequence,capture_utime_us,tx_m,ty_m,tz_m,qw,qx,qy,qz,cx_m,cy_m,cz_m,visible_fraction";
}

namespace {

// The header recordings had before their columns named units (still read).
const char* const kUnitlessHeader =
    "sequence,capture_utime,tx,ty,tz,qw,qx,qy,qz,cx,cy,cz,visible_fraction";

}  // namespace

std::string TruthCsvRow(const TruthRow& row) {
  const Eigen::Vector3f t = row.truth.target_pose.translation();
  const Eigen::Quaternionf q(row.truth.target_pose.linear());
  const Eigen::Vector3f& c = row.truth.centroid_m;
  std::ostringstream out;
  out << row.sequence << ',' << row.capture_utime;
  for (float v : {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z(), c.x(), c.y(), c.z(),
                  row.truth.visible_fraction})
    out << ',' << ShortestFloat(v);  // floats at the precision they have
  return out.str();
}

bool ReadTruthFile(const std::string& path, std::vector<TruthRow>* rows, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    return Fail(error, path + ": cannot open");
  }
  std::string line;
  if (!std::getline(in, line) || (line != TruthCsvHeader() && line != kUnitlessHeader)) {
    return Fail(error, path + ": line 1: expected the header '" + TruthCsvHeader() + "'");
  }
  rows->clear();
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(fields, cell, ',')) {
      char* end = nullptr;
      const double x = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(x)) break;
      v.push_back(x);
    }
    if (v.size() != 13) {
      return Fail(error, path + ": line " + std::to_string(number) + ": expected 13 numbers");
    }
    // The counters are whole numbers a double holds exactly (2^53), the rest fit a float:
    // a cast of anything larger is undefined (UBSan found 8.9e118 as a sequence).
    constexpr double kWhole = 9007199254740992.0;
    const auto whole = [](double x, double low) {
      return x >= low && x <= kWhole && x == std::floor(x);
    };
    if (!whole(v[0], 0) || !whole(v[1], -kWhole)) {
      return Fail(error, path + ": line " + std::to_string(number) +
                             ": sequence and capture_utime must be whole numbers within 2^53");
    }
    if (std::any_of(v.begin() + 2, v.end(),
                    [](double x) { return std::abs(x) > std::numeric_limits<float>::max(); })) {
      return Fail(error, path + ": line " + std::to_string(number) + ": a number too large");
    }
    TruthRow row;
    row.sequence = static_cast<std::uint64_t>(v[0]);
    row.capture_utime = static_cast<std::int64_t>(v[1]);
    Eigen::Quaternionf q(static_cast<float>(v[5]), static_cast<float>(v[6]),
                         static_cast<float>(v[7]), static_cast<float>(v[8]));
    if (std::abs(q.norm() - 1.0f) > 1e-3f) {
      return Fail(error,
                  path + ": line " + std::to_string(number) + ": quaternion is not unit length");
    }
    row.truth.target_pose = Eigen::Isometry3f::Identity();
    row.truth.target_pose.linear() = q.normalized().toRotationMatrix();
    row.truth.target_pose.translation() = Eigen::Vector3d(v[2], v[3], v[4]).cast<float>();
    row.truth.centroid_m = Eigen::Vector3d(v[9], v[10], v[11]).cast<float>();
    row.truth.visible_fraction = static_cast<float>(v[12]);
    rows->push_back(row);
  }
  return true;
}

}  // namespace saccade
