#include "io/lcm/fixation_log.h"

#include "core/fail.h"
#include "io/base/json.h"
#include "io/base/text.h"
#include "io/lcm/lcm_decode.h"
#include "io/lcm/lcm_log.h"

#include <lcm/lcm-cpp.hpp>
#include <saccade/fixation_t.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <memory>
#include <ostream>
#include <vector>

namespace saccade {

bool DecodeFixation(const void* data, std::size_t size, LoggedFixation* logged) {
  const std::optional<saccade::fixation_t> decoded = DecodeFixationMessage(data, size);
  if (!decoded) return false;
  const saccade::fixation_t& m = *decoded;
  if (m.mode < 0 || m.mode > static_cast<int>(AttentionMode::kFullScan)) return false;
  logged->utime = m.utime;
  logged->sensor_utime = m.sensor_utime;
  logged->frame = m.frame;
  Fixation& f = logged->fixation;
  f.frame_seq = m.seq;
  f.time_s = m.sensor_utime * 1e-6;  // the daemon's clock for a fixation
  for (int i = 0; i < 3; ++i) {
    f.fovea_m[i] = static_cast<float>(m.fovea[i]);
    f.velocity_mps[i] = static_cast<float>(m.velocity[i]);
  }
  f.growth_m = static_cast<float>(m.growth);
  f.mode = static_cast<AttentionMode>(m.mode);
  f.target = m.target;
  f.model = m.model;
  f.num_targets = m.num_targets;
  f.reason = m.reason;
  return true;
}

bool FixationWriter::FormatOf(const std::string& path, Format* format, std::string* error) {
  return TableFormatOf(path, format, error);
}

FixationWriter::FixationWriter(std::ostream& out, Format format) : out_(out), format_(format) {
  if (format_ == Format::kCsv)
    out_ << "utime_us,sensor_utime_us,seq,frame,fovea_x_m,fovea_y_m,fovea_z_m,velocity_x_mps,"
            "velocity_y_mps,velocity_z_mps,growth_m,mode,target,model,num_targets,reason\n";
}

void FixationWriter::Write(const LoggedFixation& logged) {
  const Fixation& r = logged.fixation;
  if (format_ == Format::kCsv) {
    out_ << logged.utime << ',' << logged.sensor_utime << ',' << r.frame_seq << ','
         << CsvField(logged.frame);
    for (float v : r.fovea_m) out_ << ',' << ShortestFloat(v);
    for (float v : r.velocity_mps) out_ << ',' << ShortestFloat(v);
    out_ << ',' << ShortestFloat(r.growth_m) << ',' << ModeName(r.mode) << ',' << r.target << ','
         << r.model << ',' << r.num_targets << ',' << CsvField(r.reason) << '\n';
  } else {
    JsonWriter j;
    j.BeginObject().Key("utime").Value(static_cast<long long>(logged.utime));
    j.Key("sensor_utime").Value(static_cast<long long>(logged.sensor_utime));
    j.Key("seq").Value(static_cast<long long>(r.frame_seq)).Key("frame").Value(logged.frame);
    j.Key("fovea").BeginArray();
    for (float v : r.fovea_m) j.Value(v);
    j.EndArray().Key("velocity").BeginArray();
    for (float v : r.velocity_mps) j.Value(v);
    j.EndArray().Key("growth").Value(r.growth_m);
    j.Key("mode").Value(std::string(ModeName(r.mode)));
    j.Key("target").Value(r.target).Key("model").Value(r.model);
    j.Key("num_targets").Value(r.num_targets).Key("reason").Value(r.reason).EndObject();
    out_ << j.str() << '\n';
  }
  out_.flush();
}

bool ConvertFixationLog(const std::string& log_path, const std::string& channel,
                        FixationWriter* writer, LcmLogStats* stats, std::string* error) {
  return ReadLcmLog(
      log_path, channel,
      [writer](const unsigned char* data, std::size_t size) {
        LoggedFixation r;
        if (!DecodeFixation(data, size, &r)) return false;
        writer->Write(r);
        return true;
      },
      stats, error);
}

namespace {

struct Listener {
  FixationWriter* writer;
  LcmLogStats* stats;
  const std::function<bool()>* flushed;
  bool failed = false;  // the output failed: the listening ends
  void On(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (failed) return;
    LoggedFixation r;
    if (DecodeFixation(rbuf->data, rbuf->data_size, &r)) {
      writer->Write(r);
      if (!(*flushed)()) {
        failed = true;
        return;
      }
      ++stats->written;
    } else {
      ++stats->skipped;
    }
  }
};

}  // namespace

void ListenFixations(lcm::LCM* lcm, const std::string& channel, FixationWriter* writer,
                     std::int64_t max_records, const std::atomic<bool>& stop, LcmLogStats* stats,
                     const std::function<bool()>& flushed) {
  Listener listener{writer, stats, &flushed};
  lcm::Subscription* subscription = lcm->subscribe(channel, &Listener::On, &listener);
  while (!stop && !listener.failed && (max_records <= 0 || stats->written < max_records))
    lcm->handleTimeout(200);
  lcm->unsubscribe(subscription);
}

}  // namespace saccade
