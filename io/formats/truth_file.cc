#include "io/formats/truth_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include "core/fail.h"
#include "io/base/text.h"

namespace saccade {

std::string TruthCsvHeader() {
  return "sequence,capture_utime_us,tx_m,ty_m,tz_m,qw,qx,qy,qz,cx_m,cy_m,cz_m,visible_fraction";
}

namespace {

// The header recordings had before their columns named units (still read).
const char* const kUnitlessHeader =
    "sequence,capture_utime,tx,ty,tz,qw,qx,qy,qz,cx,cy,cz,visible_fraction";

// The leading numbers of a CSV line, up to the first cell that is not a finite number.
std::vector<double> CsvNumbers(const std::string& line) {
  std::istringstream fields(line);
  std::string cell;
  std::vector<double> v;
  while (std::getline(fields, cell, ',')) {
    char* end = nullptr;
    const double x = std::strtod(cell.c_str(), &end);
    if (cell.empty() || *end != '\0' || !std::isfinite(x)) break;
    v.push_back(x);
  }
  return v;
}

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
    const std::vector<double> v = CsvNumbers(line);
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

bool ReadPoseTable(const std::string& path, std::map<int, Eigen::Isometry3f>* poses,
                   std::string* error) {
  std::ifstream in(path);
  if (!in) return Fail(error, path + ": cannot open");
  std::string header = "frame";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) header += ",T" + std::to_string(r) + std::to_string(c);
  std::string line;
  if (!std::getline(in, line) || line != header)
    return Fail(error, path + ": line 1: expected the header '" + header + "'");
  poses->clear();
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::string at = path + ": line " + std::to_string(number) + ": ";
    const std::vector<double> v = CsvNumbers(line);
    if (v.size() != 17) return Fail(error, at + "expected 17 numbers (frame, T00..T33)");
    if (!(v[0] >= 0 && v[0] <= 1e9 && v[0] == std::floor(v[0])))
      return Fail(error, at + "the frame must be a whole number >= 0");
    Eigen::Matrix4d T;
    for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = v[std::size_t(i) + 1];
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
        R.determinant() < 0 || T.row(3).cwiseAbs().sum() - 1 > 1e-6 || T(3, 3) != 1 ||
        T.col(3).head<3>().cwiseAbs().maxCoeff() > 1e6)
      return Fail(error, at + "not a rigid transform (a rotation and a translation)");
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
    pose.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix().cast<float>();
    pose.translation() = T.col(3).head<3>().cast<float>();
    if (!poses->emplace(int(v[0]), pose).second)
      return Fail(error, at + "frame " + std::to_string(int(v[0])) + " is given twice");
  }
  return true;
}

}  // namespace saccade
