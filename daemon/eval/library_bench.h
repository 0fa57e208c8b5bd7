// The library benchmark (saccade eval --cases CASES.yaml --library 1,5,10,all): every
// identity of a cases file as one model of its other captures (never the searched capture's),
// searched together in each capture the cases search, on the whole frame: which of the objects
// are there, and where. Scored against every labelled instance of identities.csv beside the
// cases file; timed per library size.
#pragma once

#include "core/parallel.h"
#include "core/recognition_options.h"

#include <Eigen/Core>

#include <ostream>
#include <string>
#include <vector>

namespace saccade::eval {

struct LibraryBenchOptions {
  std::vector<int> sizes;  // library sizes to run; 0: every identity
  RecognitionOptions recognition;
  float tolerance_m = 0.08f;  // the benchmark's 8 cm rule
  int every = 1;              // search every Nth capture (in file order)
  /// The baseline: each model described as fitted and recognized on its own (a description
  /// of the frame and an index per model), instances side by side, as before the library.
  bool separately = false;
  ParallelFor parallel = SerialFor;
  std::ostream* log = nullptr;  // progress, one line per capture
};

/// One model's instance before the library chose between models that claim one place: how
/// its arbitration can be studied (library_instances.csv).
struct LibraryInstance {
  std::string identity;  // its model's
  int label = -1;        // the labelled object of its identity within the tolerance, or -1
  bool kept = false;     // among the library's instances
  float confidence = -1, fitness = -1, coverage = -1, continued = -1;
  float colour_agreement = -1, texture_agreement = -1;
  int votes = 0;
  int matches = 0;         // the frame's descriptors its model won
  int model_points = 0;    // its model's points
  float model_size_m = 0;  // its model's size
  float spacing_m = 0;     // its model's point spacing
  Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();
};

/// One capture searched with one library.
struct LibraryRow {
  std::string scene;
  int size = 0;             // models searched
  int instances = 0;        // sure labelled instances of the library's identities
  int found = 0;            // of those, found by their own model within the tolerance
  int false_instances = 0;  // instances reported nowhere near one of their identity
  double ms = 0;            // the library search (describing the frame, matching, grouping)
  int descriptions = 0;     // descriptions of the frame it made (radii)
  double describe_ms = 0, match_ms = 0, group_ms = 0, verify_ms = 0;  // LibraryResult's
  /// The costliest of the library's models searched alone on the same frame: one model of each
  /// radius the library describes the frame at, timed alone, the slowest (0 for one model).
  /// A small radius places more keypoints, so one small model can cost what a library does.
  double costliest_alone_ms = 0;
  std::string detail;                       // "identity:found|missed|false ..." for the record
  std::vector<LibraryInstance> candidates;  // every model's instances, kept or not
};

/// Runs every size over every capture the cases search. False with `error` when a file
/// cannot be read.
bool RunLibraryBench(const std::string& cases_path, const std::string& data_dir,
                     const LibraryBenchOptions& options, std::vector<LibraryRow>* rows,
                     std::string* error);

/// Recall with its interval, false instances per capture, median ms and its ratio to the
/// smallest library's and to the library's costliest model searched alone, per size: a
/// Markdown table.
std::string LibrarySummary(const std::vector<LibraryRow>& rows);

}  // namespace saccade::eval
