// saccade labels: what a labelled scene holds, to check a detection against. Each label's
// points, centroid and extent; an mOSD object's parts (labels 10k..10k+9) also as one object k.

#include "core/types.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "io/base/json.h"
#include "io/formats/cloud_io.h"

#include <Eigen/Core>

#include <cstdio>
#include <limits>
#include <map>
#include <ostream>

namespace saccade {
namespace {

// The finite points of one label (or one object's labels): count, centroid, bounds.
struct Group {
  std::size_t points = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  std::uint32_t first_label = 0, last_label = 0;

  void Add(const Eigen::Vector3f& p, std::uint32_t label) {
    if (points == 0 || label < first_label) first_label = label;
    if (points == 0 || label > last_label) last_label = label;
    ++points;
    sum += p.cast<double>();
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Eigen::Vector3f Centroid() const { return (sum / double(points)).cast<float>(); }
};

std::string Line(const std::string& name, const Group& g) {
  const Eigen::Vector3f c = g.Centroid(), e = g.hi - g.lo;
  char line[200];
  std::snprintf(line, sizeof line,
                "%-18s %7zu points, centroid (%.3f, %.3f, %.3f) m, extent %.3f x %.3f x %.3f m",
                name.c_str(), g.points, c.x(), c.y(), c.z(), e.x(), e.y(), e.z());
  return line;
}

void GroupJson(JsonWriter* j, const Group& g) {
  j->Key("points").Value(g.points).Key("centroid_m").Vector3(g.Centroid());
  j->Key("extent_m").Vector3(Eigen::Vector3f(g.hi - g.lo));
}

}  // namespace

int RunLabels(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade labels",
            "Lists what a labelled scene (a PCD with a label field, such as mOSD's) holds: each "
            "label's finite points, centroid and extent in metres, camera frame; an mOSD "
            "object's parts (labels 10k..10k+9) also as one object k. A detection's position "
            "can be checked against these.");
  args.Positional("SCENE.pcd", "the labelled scene (required)")
      .Switch("json", "print one JSON object instead of text");
  if (auto code = args.Parse(argv, out, err)) return *code;
  if (!args.Has("SCENE.pcd")) return Usage(err, "labels", "the first argument must be a PCD file");
  const std::string path = args.Get("SCENE.pcd");
  std::string error;
  const auto scene = LoadLabelledCloud(path, &error);
  if (!scene) {
    err << "saccade labels: " << error << "\n";
    return kExitFailure;
  }
  std::map<std::uint32_t, Group> labels, objects;
  for (std::size_t i = 0; i < scene->cloud.size() && i < scene->labels.size(); ++i) {
    if (!FinitePoint(scene->cloud[i])) continue;
    const std::uint32_t label = scene->labels[i];
    const Eigen::Vector3f p = scene->cloud[i].getVector3fMap();
    labels[label].Add(p, label);
    if (label >= 10) objects[label / 10].Add(p, label);
  }
  if (args.Has("json")) {
    JsonWriter j;
    j.BeginObject().Key("scene").Value(path).Key("labels").BeginArray();
    for (const auto& [label, g] : labels) {
      j.BeginObject().Key("label").Value(int(label));
      GroupJson(&j, g);
      j.EndObject();
    }
    j.EndArray().Key("objects").BeginArray();
    for (const auto& [object, g] : objects) {
      j.BeginObject().Key("object").Value(int(object));
      j.Key("first_label").Value(int(g.first_label)).Key("last_label").Value(int(g.last_label));
      GroupJson(&j, g);
      j.EndObject();
    }
    out << j.EndArray().EndObject().str() << "\n";
    return kExitOk;
  }
  out << path << ": " << labels.size() << " label(s), " << objects.size()
      << " mOSD object(s) (labels 10k..10k+9)\n";
  for (const auto& [label, g] : labels) out << Line("label " + std::to_string(label), g) << "\n";
  for (const auto& [object, g] : objects)
    out << Line("object " + std::to_string(object) + " (" + std::to_string(g.first_label) + "-" +
                    std::to_string(g.last_label) + ")",
                g)
        << "\n";
  return kExitOk;
}

}  // namespace saccade
