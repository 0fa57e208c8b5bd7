// saccade recognize with several models (--model A.pcd,B.pcd,...): one library search.
#pragma once

#include "core/parallel.h"
#include "core/recognition.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace saccade {

/// One instance as `recognize` prints it: "instance I: [MODEL, ]votes ..., centroid (...) m,
/// ...confidence C, pose model->scene:" and the 4x4 pose, one row a line.
void PrintInstance(std::size_t index, const Detection& d, const std::string& model_name,
                   std::ostream& out);

/// Describes each model spec on the library's radius grid, searches the scene for all of them
/// at once and prints every instance with its model's name (the file's stem), as text or one
/// JSON object. Returns the exit code; one line on `err` when a model cannot be read.
int RecognizeLibraryCommand(const std::vector<std::string>& specs, const Cloud& scene,
                            const SceneQuery& query, const RecognitionOptions& options,
                            const ParallelFor& parallel, bool json, std::ostream& out,
                            std::ostream& err);

}  // namespace saccade
