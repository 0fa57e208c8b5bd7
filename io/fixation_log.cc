#include "io/fixation_log.h"

#include "core/fail.h"
#include "io/json.h"
#include "io/text.h"

#include <lcm/lcm-cpp.hpp>
#include <saccade/fixation_t.hpp>

#include <iomanip>
#include <ostream>

namespace saccade {

bool DecodeFixation(const void* data, std::size_t size, LoggedFixation* logged) {
  saccade::fixation_t m;
  if (m.decode(data, 0, static_cast<int>(size)) < 0) return false;
  if (m.mode < 0 || m.mode > static_cast<int>(AttentionMode::kFullScan)) return false;
  logged->utime = m.utime;
  logged->frame = m.frame;
  Fixation& f = logged->fixation;
  f.frame_seq = m.seq;
  f.time_s = m.utime * 1e-6;
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
  if (EndsWith(path, ".csv")) {
    *format = Format::kCsv;
  } else if (EndsWith(path, ".jsonl")) {
    *format = Format::kJsonl;
  } else {
    return Fail(error, "'" + path + "': the output must end in .csv or .jsonl");
  }
  return true;
}

FixationWriter::FixationWriter(std::ostream& out, Format format) : out_(out), format_(format) {
  if (format_ == Format::kCsv)
    out_ << "utime,seq,frame,fovea_x,fovea_y,fovea_z,velocity_x,velocity_y,velocity_z,growth,"
            "mode,target,model,num_targets,reason\n";
}

void FixationWriter::Write(const LoggedFixation& logged) {
  const Fixation& r = logged.fixation;
  if (format_ == Format::kCsv) {
    out_ << logged.utime << ',' << r.frame_seq << ',' << logged.frame << std::setprecision(9);
    for (float v : r.fovea_m) out_ << ',' << double{v};
    for (float v : r.velocity_mps) out_ << ',' << double{v};
    out_ << ',' << double{r.growth_m} << ',' << ModeName(r.mode) << ',' << r.target << ','
         << r.model << ',' << r.num_targets << ',' << r.reason << '\n';
  } else {
    JsonWriter j;
    j.BeginObject().Key("utime").Value(static_cast<long long>(logged.utime));
    j.Key("seq").Value(static_cast<long long>(r.frame_seq)).Key("frame").Value(logged.frame);
    j.Key("fovea").BeginArray();
    for (float v : r.fovea_m) j.Value(double{v});
    j.EndArray().Key("velocity").BeginArray();
    for (float v : r.velocity_mps) j.Value(double{v});
    j.EndArray()
        .Key("growth")
        .Value(double{r.growth_m})
        .Key("mode")
        .Value(std::string(ModeName(r.mode)));
    j.Key("target").Value(r.target).Key("model").Value(r.model);
    j.Key("num_targets").Value(r.num_targets).Key("reason").Value(r.reason).EndObject();
    out_ << j.str() << '\n';
  }
  out_.flush();
}

bool ConvertFixationLog(const std::string& log_path, const std::string& channel,
                        FixationWriter* writer, FixationLogStats* stats, std::string* error) {
  lcm::LogFile log(log_path, "r");
  if (!log.good()) {
    return Fail(error, "'" + log_path + "': cannot read it as an LCM log");
  }
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != channel) continue;
    LoggedFixation r;
    if (DecodeFixation(e->data, static_cast<std::size_t>(e->datalen), &r)) {
      writer->Write(r);
      ++stats->written;
    } else {
      ++stats->skipped;
    }
  }
  return true;
}

namespace {

struct Listener {
  FixationWriter* writer;
  FixationLogStats* stats;
  void On(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    LoggedFixation r;
    if (DecodeFixation(rbuf->data, rbuf->data_size, &r)) {
      writer->Write(r);
      ++stats->written;
    } else {
      ++stats->skipped;
    }
  }
};

}  // namespace

bool ListenFixations(const std::string& url, const std::string& channel, FixationWriter* writer,
                     std::int64_t max_records, const std::atomic<bool>& stop,
                     FixationLogStats* stats, std::string* error) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    return Fail(error, "cannot open LCM at '" + url + "'");
  }
  Listener listener{writer, stats};
  lcm.subscribe(channel, &Listener::On, &listener);
  while (!stop && (max_records <= 0 || stats->written < max_records)) lcm.handleTimeout(200);
  return true;
}

}  // namespace saccade
