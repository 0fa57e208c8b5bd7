#include "io/truth_file.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include "core/fail.h"

namespace saccade {

std::string TruthCsvHeader() {
  return "sequence,capture_utime,tx,ty,tz,qw,qx,qy,qz,cx,cy,cz,visible_fraction";
}

std::string TruthCsvRow(const TruthRow& row) {
  const Eigen::Vector3f t = row.truth.target_pose.translation();
  const Eigen::Quaternionf q(row.truth.target_pose.linear());
  const Eigen::Vector3f& c = row.truth.centroid_m;
  std::ostringstream out;
  out.precision(9);
  out << row.sequence << ',' << row.capture_utime << ',' << t.x() << ',' << t.y() << ',' << t.z()
      << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << c.x() << ','
      << c.y() << ',' << c.z() << ',' << row.truth.visible_fraction;
  return out.str();
}

bool ReadTruthFile(const std::string& path, std::vector<TruthRow>* rows, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    return Fail(error, path + ": cannot open");
  }
  std::string line;
  if (!std::getline(in, line) || line != TruthCsvHeader()) {
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
