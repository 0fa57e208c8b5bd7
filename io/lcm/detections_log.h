// The detections log for users: detections_t messages from an lcm-logger file as CSV (one row
// per instance) or JSON lines (one line per frame), for `saccade detections`.
#pragma once

#include "io/lcm/lcm_log.h"

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace saccade {

/// One instance_t as logged. Positions in the message's frame, metres.
struct LoggedInstance {
  std::int32_t model = -1;
  std::string model_name;
  std::array<float, 3> centroid{};     // where the object is: its points' centroid
  std::array<float, 3> translation{};  // the model's origin (X_FM), far from it for a cut model
  std::array<float, 4> quaternion{};   // X_FM's rotation: w, x, y, z
  std::int32_t votes = 0;
  float confidence = 0, fitness = 0, coverage = 0, colour_agreement = 0;
  std::int32_t track_id = -1;
  std::string track_state;
};

/// One detections_t as logged.
struct LoggedDetections {
  std::int64_t utime = 0;         // when the frame reached the host, epoch microseconds
  std::int64_t sensor_utime = 0;  // its capture time on the sensor's clock, microseconds
  std::int64_t seq = 0;
  std::int64_t publish_utime = 0;  // when saccaded published it, epoch microseconds
  std::string frame;
  bool foveated = true;
  std::array<float, 3> fovea{};
  float growth_m = 0, recognize_ms = 0, track_ms = 0;
  std::vector<LoggedInstance> instances;
};

/// Decodes one detections_t message, its layout checked first (lcm_log.h); false when the bytes
/// are not one.
bool DecodeDetections(const void* data, std::size_t size, LoggedDetections* logged);

class JsonWriter;
/// `d` as one JSON object (the fields of detections_t, instances with their `centroid`,
/// `confidence`, ...): `saccade detections --out X.jsonl`'s lines and the viewer's state.
void WriteDetectionsJson(const LoggedDetections& d, JsonWriter* j);
/// The instances alone, as a JSON array.
void WriteInstancesJson(const std::vector<LoggedInstance>& instances, JsonWriter* j);

/// Writes detections as CSV (one row per instance, the frame's fields repeated; a frame without
/// instances writes no row) or JSON lines (one line per frame, instances nested).
class DetectionWriter {
 public:
  DetectionWriter(std::ostream& out, TableFormat format);
  void Write(const LoggedDetections& logged);

 private:
  std::ostream& out_;
  TableFormat format_;
};

/// Writes every detections_t of `channel` in an lcm-logger log (ReadLcmLog: checked event by
/// event; one that does not decode is skipped and counted).
bool ConvertDetectionLog(const std::string& log_path, const std::string& channel,
                         DetectionWriter* writer, LcmLogStats* stats, std::string* error);

}  // namespace saccade
