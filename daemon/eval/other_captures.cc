#include "daemon/eval/other_captures.h"

#include "core/fail.h"
#include "core/model.h"
#include "core/recognition.h"
#include "core/sim/rerender.h"
#include "io/formats/cloud_io.h"

#include <algorithm>
#include <iomanip>
#include <limits>
#include <queue>
#include <set>

namespace saccade::eval {
namespace {

std::string IdentityOf(const LabelledCase& c) {
  return c.identity.empty() ? c.name.substr(0, c.name.find('-')) : c.identity;
}

}  // namespace

const CaptureCuts::Capture* CaptureCuts::Load(const std::string& file, std::string* error) {
  auto it = loaded_.find(file);
  if (it == loaded_.end()) {
    auto labelled = LoadLabelledCloud(file, error);
    if (!labelled) return nullptr;
    Capture c;
    if (const auto k = EstimateIntrinsics(labelled->cloud)) c.intrinsics = *k;
    c.cloud = std::make_shared<const Cloud>(std::move(labelled->cloud));
    c.labels = std::move(labelled->labels);
    it = loaded_.emplace(file, std::move(c)).first;
  }
  return &it->second;
}

const Cloud* CaptureCuts::Cut(const CaptureKey& key, std::string* error) {
  auto it = cuts_.find(key);
  if (it != cuts_.end()) return &it->second;
  const Capture* capture = Load(key.first, error);
  if (!capture) return nullptr;
  const std::vector<int> points = MosdObjectPoints(*capture->cloud, capture->labels, key.second);
  if (points.empty()) {
    Fail(error, context_ + ": " + key.first + " has no object " + std::to_string(key.second));
    return nullptr;
  }
  Cloud organized = *capture->cloud;
  std::vector<std::uint8_t> keep(organized.size(), 0);
  for (int i : points) keep[std::size_t(i)] = 1;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < organized.size(); ++i)
    if (!keep[i]) organized[i].x = organized[i].y = organized[i].z = nan;
  return &cuts_.emplace(key, std::move(organized)).first->second;
}

OtherCaptureModels::OtherCaptureModels(const std::vector<LabelledCase>& all,
                                       AlignmentOptions options, Cut cut, ParallelFor parallel,
                                       std::ostream* log)
    : options_(std::move(options)),
      cut_(std::move(cut)),
      parallel_(std::move(parallel)),
      log_(log) {
  for (const LabelledCase& c : all) {
    Identity& id = identities_[IdentityOf(c)];
    for (const CaptureKey& k :
         {CaptureKey{c.model_file, c.model_object}, CaptureKey{c.scene_file, c.scene_object}})
      if (std::find(id.captures.begin(), id.captures.end(), k) == id.captures.end())
        id.captures.push_back(k);
    if (c.truth_pose)
      truth_[{{c.model_file, c.model_object}, {c.scene_file, c.scene_object}}] = *c.truth_pose;
  }
}

bool OtherCaptureModels::Align(Identity* id) {
  const std::size_t n = id->captures.size();
  std::vector<const Cloud*> clouds(n);
  for (std::size_t i = 0; i < n; ++i)
    if (!(clouds[i] = cut_(id->captures[i]))) return false;
  id->pairs = AlignAll(clouds, options_, parallel_);
  id->aligned = true;
  // What the truth says of the alignments, where the cases give it: the capture's centroid
  // moved by the pair's own alignment, and by the chain of all captures, against the truth's.
  const auto poses = ChainViews(id->pairs, clouds, std::vector<bool>(n, true),
                                BestReference(id->pairs, clouds, std::vector<bool>(n, true)));
  int found = 0, with_truth = 0, right = 0, chained = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const Eigen::Vector3f c = *FiniteCentroid(*clouds[a]);
    for (std::size_t b = 0; b < n; ++b) {
      const ViewAlignment& ab = id->pairs[a][b];
      found += ab.found;
      const auto truth = truth_.find({id->captures[a], id->captures[b]});
      if (truth == truth_.end()) continue;
      ++with_truth;
      right += ab.found && ComparePoses(ab.pose, truth->second, c).translation_m <= 0.02;
      chained +=
          poses[a] && poses[b] &&
          ComparePoses(poses[b]->inverse() * *poses[a], truth->second, c).translation_m <= 0.02;
    }
  }
  if (log_)
    *log_ << "  aligned " << n << " captures: " << found << " of " << n * (n - 1)
          << " pairs found; of the " << with_truth << " pairs the cases give the truth of, "
          << right << " aligned and " << chained << " chained within 2 cm\n";
  return true;
}

std::optional<ViewsModel> OtherCaptureModels::For(const std::string& identity,
                                                  const CaptureKey& scene, std::string* error) {
  return Build(
      identity, scene, [&](const CaptureKey& k) { return k == scene; }, error);
}

std::optional<ViewsModel> OtherCaptureModels::ForFile(const std::string& identity,
                                                      const std::string& file, std::string* error) {
  return Build(
      identity, {file, -1}, [&](const CaptureKey& k) { return k.first == file; }, error);
}

std::vector<std::string> OtherCaptureModels::Identities() const {
  std::vector<std::string> out;
  for (const auto& [name, id] : identities_) out.push_back(name);
  return out;
}

std::optional<ViewsModel> OtherCaptureModels::Build(
    const std::string& identity, const CaptureKey& scene,
    const std::function<bool(const CaptureKey&)>& excluded, std::string* error) {
  const auto it = identities_.find(identity);
  if (it == identities_.end()) {
    Fail(error, "no capture of '" + identity + "'");
    return std::nullopt;
  }
  Identity& id = it->second;
  if (!id.aligned) {
    if (log_) *log_ << identity << ":\n";
    if (!Align(&id)) return std::nullopt;
  }
  const std::size_t n = id.captures.size();
  std::vector<bool> use(n);
  for (std::size_t i = 0; i < n; ++i) use[i] = !excluded(id.captures[i]);
  if (std::none_of(use.begin(), use.end(), [](bool u) { return u; })) {
    Fail(error, identity + ": no capture other than the scene's");
    return std::nullopt;
  }
  std::vector<const Cloud*> clouds(n);
  for (std::size_t i = 0; i < n; ++i) clouds[i] = cut_(id.captures[i]);
  const std::size_t reference = BestReference(id.pairs, clouds, use);
  const auto poses = ChainViews(id.pairs, clouds, use, reference);
  ViewsModel out;
  out.reference = id.captures[reference];
  for (std::size_t i = 0; i < n; ++i) {
    if (!use[i]) continue;
    if (poses[i])
      out.captures.push_back(id.captures[i]);
    else
      ++out.left_out;
  }
  out.views = PlaceViews(clouds, poses);
  // The truth from the reference to the scene, through the cases' poses (either direction).
  std::map<CaptureKey, Eigen::Matrix4f> reached{{out.reference, Eigen::Matrix4f::Identity()}};
  std::queue<CaptureKey> frontier;
  frontier.push(out.reference);
  while (!frontier.empty() && !reached.count(scene)) {
    const CaptureKey at = frontier.front();
    frontier.pop();
    for (const auto& [edge, pose] : truth_) {
      const auto& [from, to] = edge;
      if (from == at && !reached.count(to)) {
        reached[to] = pose * reached[at];
        frontier.push(to);
      } else if (to == at && !reached.count(from)) {
        reached[from] = pose.inverse() * reached[at];
        frontier.push(from);
      }
    }
  }
  if (const auto r = reached.find(scene); r != reached.end()) out.truth_pose = r->second;
  return out;
}

}  // namespace saccade::eval
