#include "io/lcm/detections_log.h"

#include "io/base/json.h"
#include "io/lcm/lcm_decode.h"

#include <saccade/detections_t.hpp>

#include <optional>
#include <ostream>

namespace saccade {
namespace {

template <std::size_t N>
std::array<float, N> Floats(const double (&v)[N]) {
  std::array<float, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<float>(v[i]);  // sent from floats
  return out;
}

template <std::size_t N>
void CsvFloats(std::ostream& out, const std::array<float, N>& v) {
  for (float x : v) out << ',' << ShortestFloat(x);
}

template <std::size_t N>
void JsonFloats(JsonWriter& j, const std::array<float, N>& v) {
  j.BeginArray();
  for (float x : v) j.Value(x);
  j.EndArray();
}

}  // namespace

bool DecodeDetections(const void* data, std::size_t size, LoggedDetections* logged) {
  const std::optional<saccade::detections_t> decoded = DecodeDetectionsMessage(data, size);
  if (!decoded) return false;
  const saccade::detections_t& m = *decoded;
  LoggedDetections d;
  d.utime = m.utime;
  d.sensor_utime = m.sensor_utime;
  d.seq = m.seq;
  d.publish_utime = m.publish_utime;
  d.frame = m.frame;
  d.foveated = m.foveated;
  d.fovea = Floats(m.fovea);
  d.growth_m = static_cast<float>(m.growth);
  d.recognize_ms = m.recognize_ms;
  d.track_ms = m.track_ms;
  for (const saccade::instance_t& i : m.instances) {
    LoggedInstance l;
    l.model = i.model;
    l.model_name = i.model_name;
    l.centroid = Floats(i.centroid);
    l.translation = Floats(i.trans);
    l.quaternion = Floats(i.quat);
    l.votes = i.votes;
    l.confidence = i.confidence;
    l.fitness = i.fitness;
    l.coverage = i.coverage;
    l.colour_agreement = i.colour_agreement;
    l.track_id = i.track_id;
    l.track_state = i.track_state_name;
    d.instances.push_back(std::move(l));
  }
  *logged = std::move(d);
  return true;
}

void WriteInstancesJson(const std::vector<LoggedInstance>& instances, JsonWriter* j) {
  j->BeginArray();
  for (const LoggedInstance& i : instances) {
    j->BeginObject().Key("model").Value(i.model).Key("model_name").Value(i.model_name);
    j->Key("track_id").Value(i.track_id).Key("track_state").Value(i.track_state);
    j->Key("centroid");
    JsonFloats(*j, i.centroid);
    j->Key("confidence").Value(i.confidence).Key("fitness").Value(i.fitness);
    j->Key("coverage").Value(i.coverage).Key("colour_agreement").Value(i.colour_agreement);
    j->Key("votes").Value(i.votes).Key("trans");
    JsonFloats(*j, i.translation);
    j->Key("quat");
    JsonFloats(*j, i.quaternion);
    j->EndObject();
  }
  j->EndArray();
}

void WriteDetectionsJson(const LoggedDetections& d, JsonWriter* j) {
  j->BeginObject().Key("utime").Value(static_cast<long long>(d.utime));
  j->Key("sensor_utime").Value(static_cast<long long>(d.sensor_utime));
  j->Key("seq").Value(static_cast<long long>(d.seq));
  j->Key("publish_utime").Value(static_cast<long long>(d.publish_utime));
  j->Key("frame").Value(d.frame).Key("foveated").Value(d.foveated).Key("fovea");
  JsonFloats(*j, d.fovea);
  j->Key("growth").Value(d.growth_m).Key("recognize_ms").Value(d.recognize_ms);
  j->Key("track_ms").Value(d.track_ms).Key("instances");
  WriteInstancesJson(d.instances, j);
  j->EndObject();
}

DetectionWriter::DetectionWriter(std::ostream& out, TableFormat format)
    : out_(out), format_(format) {
  if (format_ == TableFormat::kCsv)
    out_ << "utime_us,sensor_utime_us,seq,frame,model,model_name,track_id,track_state,"
            "centroid_x_m,centroid_y_m,centroid_z_m,confidence,fitness,coverage,"
            "colour_agreement,votes,trans_x_m,trans_y_m,trans_z_m,qw,qx,qy,qz,recognize_ms,"
            "track_ms\n";
}

void DetectionWriter::Write(const LoggedDetections& d) {
  if (format_ == TableFormat::kCsv) {
    for (const LoggedInstance& i : d.instances) {
      out_ << d.utime << ',' << d.sensor_utime << ',' << d.seq << ',' << CsvField(d.frame) << ','
           << i.model << ',' << CsvField(i.model_name) << ',' << i.track_id << ','
           << CsvField(i.track_state);
      CsvFloats(out_, i.centroid);
      CsvFloats(out_,
                std::array<float, 4>{i.confidence, i.fitness, i.coverage, i.colour_agreement});
      out_ << ',' << i.votes;
      CsvFloats(out_, i.translation);
      CsvFloats(out_, i.quaternion);
      CsvFloats(out_, std::array<float, 2>{d.recognize_ms, d.track_ms});
      out_ << '\n';
    }
  } else {
    JsonWriter j;
    WriteDetectionsJson(d, &j);
    out_ << j.str() << '\n';
  }
  out_.flush();
}

bool ConvertDetectionLog(const std::string& log_path, const std::string& channel,
                         DetectionWriter* writer, LcmLogStats* stats, std::string* error) {
  return ReadLcmLog(
      log_path, channel,
      [writer](const unsigned char* data, std::size_t size) {
        LoggedDetections d;
        if (!DecodeDetections(data, size, &d)) return false;
        writer->Write(d);
        return true;
      },
      stats, error);
}

}  // namespace saccade
