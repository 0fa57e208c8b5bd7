#include "daemon/eval/library_bench.h"

#include "core/eval/evaluation.h"
#include "core/fail.h"
#include "core/library.h"
#include "core/model.h"
#include "daemon/eval/evaluation.h"
#include "daemon/eval/other_captures.h"
#include "io/config/config.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <sstream>

namespace saccade::eval {
namespace {

namespace fs = std::filesystem;

// One labelled object of a capture (identities.csv).
struct Labelled {
  std::string identity;
  int object = 0;
  bool sure = false;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
};

std::string Normal(const fs::path& p) { return p.lexically_normal().string(); }

// identities.csv beside the cases file: capture (normalized path) -> its labelled objects
// (centroids not yet measured).
bool ReadIdentities(const std::string& cases_path,
                    std::map<std::string, std::vector<Labelled>>* out, std::string* error) {
  const fs::path dir = fs::path(cases_path).parent_path();
  const fs::path file = dir / "identities.csv";
  std::ifstream in(file);
  if (!in) return Fail(error, file.string() + ": cannot read it (the library benchmark needs it)");
  std::string line;
  std::getline(in, line);  // header: scene,object,identity,confidence,...
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (cells.size() < 4)
      return Fail(error, file.string() + ":" + std::to_string(row) +
                             ": expected scene,object,"
                             "identity,confidence");
    Labelled l;
    l.identity = cells[2];
    l.sure = cells[3] == "sure";
    try {
      l.object = std::stoi(cells[1]);
    } catch (const std::exception&) {
      return Fail(error, file.string() + ":" + std::to_string(row) + ": object '" + cells[1] +
                             "' is not a number");
    }
    (*out)[Normal(dir / cells[0])].push_back(l);
  }
  return true;
}

// A described model of several captures, and how its instances are scored.
struct LibraryModel {
  std::string identity;
  std::unique_ptr<ModelDescription> description;
  EvalModel scored;
};

// The slowest search of one of `models` alone on `scene`: one model of each SHOT radius (each
// radius is one description of the frame, the bulk of a search's cost), timed as a library of
// that model alone.
double CostliestAloneMs(const std::vector<const ModelDescription*>& models, const Cloud& scene,
                        const SceneQuery& query, const LibraryBenchOptions& options) {
  std::set<float> radii;
  double costliest = 0;
  for (const ModelDescription* m : models) {
    if (!radii.insert(m->scale().shot_radius_m).second) continue;
    const Library alone({m}, options.recognition);
    const auto t0 = std::chrono::steady_clock::now();
    RecognizeLibrary(alone, scene, query, options.recognition, {}, options.parallel);
    costliest = std::max(
        costliest,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return costliest;
}

}  // namespace

bool RunLibraryBench(const std::string& cases_path, const std::string& data_dir,
                     const LibraryBenchOptions& options, std::vector<LibraryRow>* rows,
                     std::string* error) {
  std::vector<LabelledCase> cases;
  if (!LoadLabelledCases(cases_path, data_dir, &cases, error)) return false;
  std::map<std::string, std::vector<Labelled>> labelled;
  if (!ReadIdentities(cases_path, &labelled, error)) return false;
  CaptureCuts captures(cases_path);
  OtherCaptureModels others(
      cases, AlignmentOptions{}, [&](const CaptureKey& k) { return captures.Cut(k, error); },
      options.parallel, nullptr);
  const std::vector<std::string> identities = others.Identities();
  std::set<std::string> scenes;
  for (const LabelledCase& c : cases) scenes.insert(c.scene_file);

  // An identity with no capture in the searched one is searched with its model of every
  // capture, described once; one with a capture there with a model of the others, described
  // for that capture and dropped after it (a model of ten organized captures is large).
  std::map<std::string, std::unique_ptr<LibraryModel>> whole;
  std::map<std::string, std::unique_ptr<LibraryModel>> this_capture;
  std::map<std::string, std::vector<CaptureKey>> all_captures;
  std::map<std::string, const LibraryModel*> chosen;  // this capture's, once per identity
  const auto describe = [&](const std::string& identity,
                            ViewsModel views) -> std::unique_ptr<LibraryModel> {
    std::string why;
    std::optional<ModelDescription> d =
        DescribeModel(views.views, options.recognition, &why,
                      options.separately ? 1.0f : options.recognition.library_radius_ratio);
    if (!d) {
      Fail(error, identity + ": " + why);
      return nullptr;
    }
    auto m = std::make_unique<LibraryModel>();
    m->identity = identity;
    m->description = std::make_unique<ModelDescription>(std::move(*d));
    m->scored = ViewsEvalModel(std::move(views.views));
    m->scored.views.clear();  // scored by its sample alone
    m->scored.cloud.clear();
    return m;
  };
  const auto model_of = [&](const std::string& identity,
                            const std::string& scene) -> const LibraryModel* {
    if (const auto it = chosen.find(identity); it != chosen.end()) return it->second;
    std::optional<ViewsModel> views = others.ForFile(identity, scene, error);
    if (!views) return nullptr;
    auto& every_capture = all_captures[identity];
    if (every_capture.empty()) {
      std::optional<ViewsModel> all = others.ForFile(identity, "", error);
      if (!all) return nullptr;
      every_capture = all->captures;
    }
    auto& slot = views->captures == every_capture ? whole[identity] : this_capture[identity];
    if (!slot) slot = describe(identity, std::move(*views));
    return chosen[identity] = slot.get();
  };

  std::size_t scene_index = 0;
  for (const std::string& scene : scenes) {
    if (scene_index++ % std::size_t(std::max(1, options.every)) != 0) continue;
    this_capture.clear();
    chosen.clear();
    const CaptureCuts::Capture* capture = captures.Load(scene, error);
    if (!capture) return false;
    const auto labels = labelled.find(Normal(scene));
    if (labels == labelled.end())
      return Fail(error, scene + ": not in identities.csv beside " + cases_path +
                             " (the library benchmark scores against its labels)");
    std::vector<Labelled> truth = labels->second;
    for (Labelled& l : truth) {
      const Cloud* cut = captures.Cut({scene, l.object}, error);
      if (!cut) return false;
      l.centroid = *FiniteCentroid(*cut);
    }
    // The identities present first (a library of one searches for one that is there), then
    // the others in an order seeded by the capture.
    std::vector<std::string> order, absent;
    for (const std::string& id : identities)
      (std::any_of(truth.begin(), truth.end(),
                   [&](const Labelled& l) { return l.sure && l.identity == id; })
           ? order
           : absent)
          .push_back(id);
    std::mt19937 rng{unsigned(scene_index)};
    std::shuffle(absent.begin(), absent.end(), rng);
    order.insert(order.end(), absent.begin(), absent.end());

    for (int size : options.sizes) {
      const std::size_t n = size <= 0 ? order.size() : std::min(order.size(), std::size_t(size));
      std::vector<const LibraryModel*> models;
      for (std::size_t i = 0; i < n; ++i) {
        const LibraryModel* m = model_of(order[i], scene);
        if (!m) return false;
        models.push_back(m);
      }
      std::vector<const ModelDescription*> descriptions;
      for (const LibraryModel* m : models) descriptions.push_back(m->description.get());
      const Library library(descriptions, options.recognition);
      SceneQuery query;
      query.foveated = false;
      query.intrinsics = capture->intrinsics;
      const auto t0 = std::chrono::steady_clock::now();
      std::string why;
      LibraryResult result;
      if (options.separately) {  // as saccaded searched several models before the library
        for (std::size_t m = 0; m < descriptions.size(); ++m) {
          RecognitionResult r = Recognize(*descriptions[m], *capture->cloud, query,
                                          options.recognition, options.parallel, &why);
          for (Detection& d : r.instances) {
            d.model = int(m);
            result.instances.push_back(std::move(d));
          }
          ++result.scene_descriptions;
        }
      } else {
        result = RecognizeLibrary(library, *capture->cloud, query, options.recognition, {},
                                  options.parallel, &why);
      }
      LibraryRow row;
      row.ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      row.scene = scene;
      row.size = int(n);
      row.descriptions = int(result.scene_descriptions);
      row.describe_ms = result.describe_ms;
      row.match_ms = result.match_ms;
      row.group_ms = result.group_ms;
      row.verify_ms = result.verify_ms;
      if (n > 1 && !options.separately)
        row.costliest_alone_ms = CostliestAloneMs(descriptions, *capture->cloud, query, options);
      std::vector<bool> claimed(truth.size(), false);
      // The nearest labelled object of `d`'s identity within the tolerance and not in `taken`
      // (may be null): its index into `truth`, or truth.size().
      const auto nearest_label = [&](const Detection& d, const std::vector<bool>* taken) {
        const LibraryModel& m = *models[std::size_t(d.model)];
        const Eigen::Vector3f at = m.scored.ScoredPoint(d.model_to_scene);
        std::size_t best = truth.size();
        float best_distance = options.tolerance_m;
        for (std::size_t t = 0; t < truth.size(); ++t) {
          const float distance = (truth[t].centroid - at).norm();
          if (!(taken && (*taken)[t]) && truth[t].identity == m.identity &&
              distance <= best_distance)
            best = t, best_distance = distance;
        }
        return best;
      };
      std::ostringstream detail;
      for (const Detection& d : result.instances) {
        const LibraryModel& m = *models[std::size_t(d.model)];
        const std::size_t best = nearest_label(d, &claimed);
        char confidence[16];
        std::snprintf(confidence, sizeof confidence, ":%.3f ", double(d.confidence));
        if (best < truth.size()) {
          claimed[best] = true;
          detail << m.identity << ":true" << confidence;
        } else {
          ++row.false_instances;
          detail << m.identity << ":false" << confidence;
        }
      }
      for (std::size_t t = 0; t < truth.size(); ++t) {
        const bool searched = std::find(order.begin(), order.begin() + long(n),
                                        truth[t].identity) != order.begin() + long(n);
        if (!truth[t].sure || !searched) continue;
        ++row.instances;
        row.found += claimed[t];
        if (!claimed[t]) detail << truth[t].identity << ":missed ";
      }
      for (const RecognitionResult& r : result.per_model)
        for (const Detection& d : r.instances) {
          const LibraryModel& m = *models[std::size_t(d.model)];
          LibraryInstance c;
          c.identity = m.identity;
          if (const std::size_t t = nearest_label(d, nullptr); t < truth.size())
            c.label = truth[t].object;
          c.kept =
              std::any_of(result.instances.begin(), result.instances.end(), [&](const auto& k) {
                return k.model == d.model && k.model_to_scene == d.model_to_scene;
              });
          c.confidence = d.confidence;
          c.fitness = d.fitness;
          c.coverage = d.coverage;
          c.continued = d.continued;
          c.colour_agreement = d.colour_agreement;
          c.texture_agreement = d.texture_agreement;
          c.votes = d.votes;
          c.matches = int(r.stats.correspondences);
          c.model_points = int(m.description->cloud().size());
          c.model_size_m = m.description->scale().size_m;
          c.spacing_m = m.description->scale().spacing_m;
          c.centroid_m = d.centroid_m;
          row.candidates.push_back(c);
        }
      row.detail = detail.str();
      if (!row.detail.empty()) row.detail.pop_back();
      if (options.log)
        *options.log << scene << " library " << row.size << ": " << row.found << "/"
                     << row.instances << " found, " << row.false_instances << " false, "
                     << row.descriptions << " descriptions, " << int(row.ms) << " ms (describe "
                     << int(row.describe_ms) << ", match " << int(row.match_ms) << ", group "
                     << int(row.group_ms) << ", verify " << int(row.verify_ms) << ")\n";
      rows->push_back(std::move(row));
    }
  }
  return true;
}

std::string LibrarySummary(const std::vector<LibraryRow>& rows) {
  std::map<int, std::vector<const LibraryRow*>> by_size;
  for (const LibraryRow& r : rows) by_size[r.size].push_back(&r);
  const auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  std::ostringstream out;
  out << "| models | captures | recall | false a capture | descriptions a frame (median) | "
         "ms a frame, median | against the smallest | against its costliest model alone "
         "(median) |\n|---|---|---|---|---|---|---|---|\n";
  double first_ms = 0;
  for (const auto& [size, list] : by_size) {
    int instances = 0, found = 0, false_instances = 0;
    std::vector<double> ms, descriptions, against_alone;
    for (const LibraryRow* r : list) {
      if (r->costliest_alone_ms > 0) against_alone.push_back(r->ms / r->costliest_alone_ms);
      instances += r->instances;
      found += r->found;
      false_instances += r->false_instances;
      ms.push_back(r->ms);
      descriptions.push_back(r->descriptions);
    }
    const Interval ci = WilsonInterval(found, instances);
    const double m = median(ms);
    if (first_ms == 0) first_ms = m;
    char alone[32] = "-";
    if (!against_alone.empty()) std::snprintf(alone, sizeof alone, "%.2fx", median(against_alone));
    char line[288];
    std::snprintf(
        line, sizeof line,
        "| %d | %zu | %d/%d (%.0f%%, CI %.0f-%.0f%%) | %.2f | %.0f | %.0f | %.2fx | %s |\n", size,
        list.size(), found, instances, instances ? 100.0 * found / instances : 0.0, 100 * ci.low,
        100 * ci.high, list.empty() ? 0.0 : double(false_instances) / double(list.size()),
        median(descriptions), m, first_ms > 0 ? m / first_ms : 0.0, alone);
    out << line;
  }
  return out.str();
}

}  // namespace saccade::eval
