// truth.csv: the ground truth of a recorded sequence, one row per frame file, in file order.
#pragma once

#include "core/sim/scenario.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace saccade {

constexpr char kTruthFileName[] = "truth.csv";

struct TruthRow {
  std::uint64_t sequence = 0;
  std::int64_t capture_utime = 0;
  GroundTruth truth;
};

/// The header line (without newline) and one row: sequence, capture_utime, target pose as
/// tx ty tz (m) and qw qx qy qz, centroid cx cy cz (m), visible_fraction.
std::string TruthCsvHeader();
std::string TruthCsvRow(const TruthRow& row);

/// False with `error` = "PATH: line N: reason" on a malformed file.
bool ReadTruthFile(const std::string& path, std::vector<TruthRow>* rows, std::string* error);

/// A table of an object's pose per frame, as recorded by others (`frame,T00,T01,...,T33`: the
/// frame's index in the sequence, then the 4 x 4 object-to-camera transform row by row, metres).
/// Fills `poses` by frame index; frames without a row have no truth. False with `error` =
/// "PATH: line N: reason" on a malformed file (a bad header, a frame twice, a row that is not a
/// rigid transform).
bool ReadPoseTable(const std::string& path, std::map<int, Eigen::Isometry3f>* poses,
                   std::string* error);

}  // namespace saccade
