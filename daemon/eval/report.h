// `saccade eval`'s report on cross-capture cases: recall with its interval on the feasible cases,
// false instances per case, time, pose errors against the truth pose, per object and per category,
// where each miss was lost, and a cross-validation of the choice of configuration across objects.
#pragma once

#include "daemon/eval/evaluation.h"

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace saccade::eval {

/// Writes `report.md` and `cases.csv` into `dir` for `runs` (per configuration, its protocols)
/// and prints the headline rows to `out`; false with one line when a file cannot be written.
bool WriteCaseReport(const std::string& cases_file, const std::vector<EvalConfiguration>& configs,
                     const std::vector<EvalModel>& models, const std::vector<Scene>& scenes,
                     const std::vector<std::vector<ProtocolRun>>& runs,
                     const std::filesystem::path& dir, std::ostream& out, std::string* error);

}  // namespace saccade::eval
