#include "io/viewer/viewer.h"

#include "core/fixation.h"
#include "io/base/json.h"
#include "io/lcm/bus.h"
#include "io/lcm/detections_log.h"
#include "io/lcm/fixation_log.h"
#include "io/lcm/lcm_decode.h"
#include "io/lcm/lcm_log.h"
#include "io/lcm/preview.h"

#include <saccade/status_t.hpp>

#include <algorithm>
#include <deque>
#include <map>
#include <mutex>
#include <optional>

namespace saccade {
namespace {

/// One point of the strips: the viewer's clock and a value.
struct Sample {
  double t_s;
  double value;
};

void Strip(JsonWriter* j, const std::string& name, const std::deque<Sample>& samples,
           double now_s) {
  j->Key(name).BeginArray();
  for (const Sample& s : samples) {
    j->BeginArray().Value(s.t_s - now_s).Value(s.value).EndArray();
  }
  j->EndArray();
}

void Array3(JsonWriter* j, const std::array<float, 3>& v) {
  j->BeginArray().Value(v[0]).Value(v[1]).Value(v[2]).EndArray();
}

template <std::size_t N>
void Doubles(JsonWriter* j, const std::array<double, N>& v) {
  j->BeginArray();
  for (double x : v) j->Value(x);
  j->EndArray();
}

}  // namespace

struct ViewerState::Impl {
  explicit Impl(const ViewerOptions& o) : options(o) {}

  // Keeps history_s of samples and at most kMaxSamples: saccaded sends a status at most 20
  // times a second, and a flood of messages must not grow the page without bound.
  void Push(std::deque<Sample>* strip, double t_s, double value) {
    strip->push_back({t_s, value});
    while (strip->size() > kMaxSamples ||
           (!strip->empty() && strip->front().t_s < t_s - options.history_s))
      strip->pop_front();
  }
  static constexpr std::size_t kMaxSamples = 4096;

  const ViewerOptions options;
  mutable std::mutex mutex;
  double heard_s = -1;  // when the last message came (steady), -1: never
  std::int64_t rejected = 0;
  std::optional<LoggedDetections> detections;
  std::map<std::int64_t, LoggedDetections> recent;  // by seq, the last few: a preview's frame
  std::optional<LoggedFixation> fixation;
  std::deque<std::array<float, 3>> trail;  // the last fixations' foveas, oldest first
  std::optional<saccade::status_t> status;
  std::optional<DecodedPreview> preview;
  std::deque<Sample> fps, dropped, recognize_ms, capture_to_publish_ms, growth, mode;
  double last_growth_sample_s = -1;
  std::int64_t last_dropped = -1;
};

ViewerState::ViewerState(const ViewerOptions& options) : impl_(std::make_unique<Impl>(options)) {}
ViewerState::~ViewerState() = default;

bool ViewerState::OnMessage(const std::string& channel, const void* data, std::size_t size,
                            double now_s) {
  const std::string& prefix = impl_->options.channel_prefix;
  Impl& s = *impl_;
  if (channel == DetectionsChannel(prefix)) {
    LoggedDetections d;
    const bool ok = DecodeDetections(data, size, &d);
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!ok) return ++s.rejected, false;
    s.heard_s = now_s;
    s.recent[d.seq] = d;
    while (s.recent.size() > 64) s.recent.erase(s.recent.begin());
    s.detections = std::move(d);
    return true;
  }
  if (channel == FixationChannel(prefix)) {
    LoggedFixation f;
    const bool ok = DecodeFixation(data, size, &f);
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!ok) return ++s.rejected, false;
    s.heard_s = now_s;
    const Eigen::Vector3f& p = f.fixation.fovea_m;
    s.trail.push_back({p.x(), p.y(), p.z()});
    while (s.trail.size() > 60) s.trail.pop_front();
    // G and the mode at most 10 times a second: a minute's strip stays small.
    if (s.last_growth_sample_s < 0 || now_s - s.last_growth_sample_s >= 0.1) {
      s.last_growth_sample_s = now_s;
      s.Push(&s.growth, now_s, f.fixation.growth_m);
      s.Push(&s.mode, now_s, static_cast<int>(f.fixation.mode));
    }
    s.fixation = std::move(f);
    return true;
  }
  if (channel == StatusChannel(prefix)) {
    std::optional<saccade::status_t> m = DecodeStatusMessage(data, size);
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!m) return ++s.rejected, false;
    s.heard_s = now_s;
    s.Push(&s.fps, now_s, m->fps);
    // Drops since the last status, in double: the counts are the sender's (any int64), and a
    // restarted daemon starts again from 0.
    const double dropped =
        static_cast<double>(m->frames_dropped) - static_cast<double>(s.last_dropped);
    s.Push(&s.dropped, now_s, s.last_dropped < 0 ? 0.0 : std::max(0.0, dropped));
    s.last_dropped = m->frames_dropped;
    for (const saccade::stage_latency_t& st : m->stages) {
      if (st.samples <= 0) continue;
      if (st.name == "recognize") s.Push(&s.recognize_ms, now_s, st.p50_ms);
      if (st.name == "capture_to_publish") s.Push(&s.capture_to_publish_ms, now_s, st.p50_ms);
    }
    s.status = std::move(m);
    return true;
  }
  if (channel == PreviewChannel(prefix)) {
    std::optional<DecodedPreview> p = DecodePreview(data, size, nullptr);
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!p) return ++s.rejected, false;
    s.heard_s = now_s;
    s.preview = std::move(p);
    return true;
  }
  return false;  // another channel: not ours
}

std::string ViewerState::StateJson(double now_s) const {
  const Impl& s = *impl_;
  std::lock_guard<std::mutex> lock(s.mutex);
  JsonWriter j;
  const double ago = s.heard_s < 0 ? -1 : now_s - s.heard_s;
  j.BeginObject().Key("connected").Value(s.heard_s >= 0 && ago <= s.options.stale_after_s);
  j.Key("heard_s_ago").Value(ago).Key("lcm_url").Value(s.options.lcm_url);
  j.Key("channel_prefix").Value(s.options.channel_prefix);
  j.Key("rejected").Value(static_cast<long long>(s.rejected));

  j.Key("detections");
  LoggedDetections none;
  if (s.detections) {
    WriteDetectionsJson(*s.detections, &j);
  } else {
    j.Null();
  }
  // The newest frame's instances again at the top, as most readers want them.
  j.Key("instances");
  WriteInstancesJson(s.detections ? s.detections->instances : none.instances, &j);

  j.Key("fixation");
  if (s.fixation) {
    const Fixation& f = s.fixation->fixation;
    j.BeginObject().Key("utime").Value(static_cast<long long>(s.fixation->utime));
    j.Key("seq").Value(static_cast<long long>(f.frame_seq)).Key("frame").Value(s.fixation->frame);
    j.Key("fovea").Vector3(f.fovea_m).Key("velocity").Vector3(f.velocity_mps);
    j.Key("growth").Value(f.growth_m).Key("mode").Value(std::string(ModeName(f.mode)));
    j.Key("target").Value(f.target).Key("model").Value(f.model);
    j.Key("num_targets").Value(f.num_targets).Key("reason").Value(f.reason).EndObject();
  } else {
    j.Null();
  }
  j.Key("trail").BeginArray();
  for (const auto& p : s.trail) Array3(&j, p);
  j.EndArray();

  j.Key("status");
  if (s.status) {
    const saccade::status_t& m = *s.status;
    j.BeginObject().Key("uptime_s").Value(m.uptime_s).Key("source").Value(m.source);
    j.Key("source_state").Value(m.source_state).Key("paused").Value(m.paused);
    j.Key("fps").Value(m.fps);
    j.Key("frames_in").Value(static_cast<long long>(m.frames_in));
    j.Key("frames_processed").Value(static_cast<long long>(m.frames_processed));
    j.Key("frames_dropped").Value(static_cast<long long>(m.frames_dropped));
    j.Key("frames_skipped").Value(static_cast<long long>(m.frames_skipped));
    j.Key("frames_unsent").Value(static_cast<long long>(m.frames_unsent));
    j.Key("commands_rejected").Value(static_cast<long long>(m.commands_rejected));
    j.Key("lcm_datagrams_dropped").Value(static_cast<long long>(m.lcm_datagrams_dropped));
    j.Key("stages").BeginObject();
    for (const saccade::stage_latency_t& st : m.stages) {
      j.Key(st.name).BeginObject().Key("samples").Value(st.samples);
      j.Key("p50_ms").Value(st.p50_ms).Key("p99_ms").Value(st.p99_ms).EndObject();
    }
    j.EndObject().EndObject();
  } else {
    j.Null();
  }

  j.Key("history").BeginObject();
  Strip(&j, "fps", s.fps, now_s);
  Strip(&j, "dropped", s.dropped, now_s);
  Strip(&j, "recognize_ms", s.recognize_ms, now_s);
  Strip(&j, "capture_to_publish_ms", s.capture_to_publish_ms, now_s);
  Strip(&j, "growth_m", s.growth, now_s);
  Strip(&j, "mode", s.mode, now_s);
  j.EndObject();

  j.Key("preview");
  if (s.preview) {
    const DecodedPreview& p = *s.preview;
    j.BeginObject().Key("seq").Value(static_cast<long long>(p.seq));
    j.Key("width").Value(p.width).Key("height").Value(p.height);
    j.Key("fx").Value(p.fx).Key("fy").Value(p.fy).Key("cx").Value(p.cx).Key("cy").Value(p.cy);
    j.Key("colour").Value(p.colour).Key("num_points").Value(p.num_points);
    j.Key("box_trans");
    Doubles(&j, p.box_trans);
    j.Key("box_quat");
    Doubles(&j, p.box_quat);
    j.Key("levels").BeginArray();
    for (std::size_t k = 0; k < p.level_min.size(); ++k) {
      j.BeginObject().Key("min");
      Array3(&j, p.level_min[k]);
      j.Key("max");
      Array3(&j, p.level_max[k]);
      j.EndObject();
    }
    j.EndArray().Key("fovea");
    Doubles(&j, p.fovea);
    j.Key("growth").Value(p.growth).Key("truth");
    if (p.has_truth) {
      Array3(&j, p.truth_centroid);
    } else {
      j.Null();
    }
    // The preview's instances (camera frame), with what the frame's detections say of each.
    const auto frame = s.recent.find(p.seq);
    j.Key("instances").BeginArray();
    for (std::size_t i = 0; i < p.instance_centroids.size(); ++i) {
      j.BeginObject().Key("centroid");
      Array3(&j, p.instance_centroids[i]);
      if (frame != s.recent.end() && i < frame->second.instances.size()) {
        const LoggedInstance& l = frame->second.instances[i];
        j.Key("model_name").Value(l.model_name).Key("track_id").Value(l.track_id);
        j.Key("track_state").Value(l.track_state).Key("confidence").Value(l.confidence);
      }
      j.EndObject();
    }
    j.EndArray().EndObject();
  } else {
    j.Null();
  }
  j.EndObject();
  return j.str();
}

std::vector<std::uint8_t> ViewerState::PreviewImage(std::int64_t seq) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (!impl_->preview || (seq >= 0 && seq != impl_->preview->seq)) return {};
  return impl_->preview->image;
}

std::vector<std::uint8_t> ViewerState::PreviewPoints(std::int64_t seq) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (!impl_->preview || (seq >= 0 && seq != impl_->preview->seq)) return {};
  return impl_->preview->points;
}

}  // namespace saccade
