#include "daemon/eval/other_captures.h"

#include "core/fail.h"
#include "core/model.h"
#include "core/recognition.h"

#include <algorithm>
#include <iomanip>
#include <queue>
#include <set>

namespace saccade::eval {
namespace {

std::string IdentityOf(const LabelledCase& c) {
  return c.identity.empty() ? c.name.substr(0, c.name.find('-')) : c.identity;
}

}  // namespace

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
  for (std::size_t i = 0; i < n; ++i) use[i] = id.captures[i] != scene;
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
