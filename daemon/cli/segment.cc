// saccade segment: cut an object out of a capture and write it as a model (paper §5.8.1).

#include "core/fail.h"
#include "core/segmentation.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/cli/pick.h"
#include "io/base/json.h"
#include "io/formats/cloud_io.h"

#include <cmath>
#include <iomanip>
#include <ostream>

namespace saccade {
namespace {

std::string SegmentationJson(const Segmentation& s, std::size_t picked, const std::string& out) {
  JsonWriter j;
  j.BeginObject().Key("finite_points").Value(s.finite_points);
  j.Key("kept_points").Value(s.kept_points).Key("planes").BeginArray();
  for (const Plane& p : s.planes) {
    j.BeginObject().Key("coefficients").BeginArray();
    for (int k = 0; k < 4; ++k) j.Value(double(p.coefficients[k]));
    j.EndArray().Key("points").Value(p.inliers).EndObject();
  }
  j.EndArray().Key("clusters").BeginArray();
  for (std::size_t i = 0; i < s.clusters.size(); ++i) {
    const Cluster& c = s.clusters[i];
    j.BeginObject().Key("index").Value(i).Key("points").Value(c.indices.size());
    j.Key("centroid").Vector3(c.centroid_m);
    j.Key("box_min").Vector3(c.box.min);
    j.Key("box_max").Vector3(c.box.max);
    j.EndObject();
  }
  j.EndArray().Key("picked").Value(picked).Key("out").Value(out).EndObject();
  return j.str();
}

void PrintSegmentation(const Segmentation& s, std::size_t picked, const std::string& out,
                       std::ostream& os) {
  os << std::fixed << std::setprecision(3);
  os << s.finite_points << " finite points, " << s.kept_points << " within z_max; "
     << s.planes.size() << " plane(s) removed:";
  for (const Plane& p : s.planes) os << " " << p.inliers;
  os << "\n" << s.clusters.size() << " cluster(s), largest first:\n";
  for (std::size_t i = 0; i < s.clusters.size(); ++i) {
    const Cluster& c = s.clusters[i];
    const Eigen::Vector3f size = c.box.Size();
    os << (i == picked ? "* " : "  ") << i << ": " << c.indices.size() << " points, centroid ("
       << c.centroid_m.x() << ", " << c.centroid_m.y() << ", " << c.centroid_m.z() << ") m, size "
       << size.x() << " x " << size.y() << " x " << size.z() << " m\n";
  }
  os << "wrote cluster " << picked << " to " << out << "\n";
}

}  // namespace

std::optional<PickRule> ParsePick(const std::string& text) {
  if (text == "largest") return PickRule{PickRule::Kind::kLargest, 0};
  if (text == "nearest") return PickRule{PickRule::Kind::kNearest, 0};
  const auto n = Args::ParseNumber(text);
  if (!n || *n < 0 || *n != std::floor(*n)) return std::nullopt;
  return PickRule{PickRule::Kind::kIndex, std::size_t(*n)};
}

// The cluster the rule picks (clusters come largest first), or nullopt with `error`.
std::optional<std::size_t> Pick(const PickRule& rule, const Segmentation& s, std::string* error) {
  switch (rule.kind) {
    case PickRule::Kind::kLargest:
      return 0;
    case PickRule::Kind::kNearest: {
      std::size_t best = 0;
      for (std::size_t i = 1; i < s.clusters.size(); ++i)
        if (s.clusters[i].centroid_m.norm() < s.clusters[best].centroid_m.norm()) best = i;
      return best;
    }
    case PickRule::Kind::kIndex:
      break;
  }
  if (rule.index >= s.clusters.size()) {
    Fail(error, "--pick " + std::to_string(rule.index) + ": only " +
                    std::to_string(s.clusters.size()) + " cluster(s) found (indices from 0)");
    return std::nullopt;
  }
  return rule.index;
}

int RunSegment(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade segment",
            "Cuts an object out of a capture: drops points beyond --z-max, removes planes "
            "until --plane-fraction of the points is gone, clusters the rest and writes the "
            "picked cluster as a model (kept in the capture's camera frame).");
  const SegmentationOptions defaults;
  args.Value("scene", "S.pcd", "the capture (required)")
      .Value("out", "MODEL.pcd", "the model to write (required)")
      .Value("z-max", "M", "drop points farther than M metres" + Args::Default(defaults.z_max_m))
      .Value("plane-fraction", "F",
             "remove planes until this fraction of the points is gone" +
                 Args::Default(defaults.plane_fraction))
      .Value("plane-distance", "D",
             "a point within D metres of a plane belongs to it" +
                 Args::Default(defaults.plane_distance_m))
      .Value("cluster-distance", "D",
             "neighbours closer than D metres join a cluster" +
                 Args::Default(defaults.cluster_distance_m))
      .Value("min-points", "N",
             "drop clusters of fewer points" + Args::Default(defaults.min_points))
      .Value("pick", "RULE",
             "largest, nearest (to the camera) or a cluster's index "
             "(default: largest)")
      .Value("seed", "N", "RANSAC's seed, a whole number >= 1" + Args::Default(defaults.seed))
      .Switch("json", "print one JSON object instead of text");
  if (auto code = args.Parse(argv, out, err)) return *code;
  std::string error;
  for (const char* required : {"scene", "out"})
    if (!args.Has(required)) return Usage(err, "segment", std::string("missing --") + required);
  SegmentationOptions options;
  for (auto [flag, field] : {std::pair<const char*, float*>{"z-max", &options.z_max_m},
                             {"plane-fraction", &options.plane_fraction},
                             {"plane-distance", &options.plane_distance_m},
                             {"cluster-distance", &options.cluster_distance_m}}) {
    if (!args.Has(flag)) continue;
    const auto v = Args::ParseNumber(args.Get(flag));
    if (!v) return Usage(err, "segment", std::string("--") + flag + " expects a number");
    *field = static_cast<float>(*v);
  }
  if (args.Has("min-points")) {
    const auto v = Args::ParsePositiveInt(args.Get("min-points"));
    if (!v) return Usage(err, "segment", "--min-points expects a positive integer");
    options.min_points = *v;
  }
  if (args.Has("seed")) {
    const auto v = Args::ParsePositiveInt(args.Get("seed"));
    if (!v) return Usage(err, "segment", "--seed expects a positive integer");
    options.seed = static_cast<std::uint32_t>(*v);
  }
  if (!options.IsValid(&error)) {
    // The options name their fields; the user typed flags.
    for (const auto& [field, flag] : {std::pair<std::string, std::string>{"z_max", "--z-max"},
                                      {"plane_fraction", "--plane-fraction"},
                                      {"plane_distance", "--plane-distance"},
                                      {"cluster_distance", "--cluster-distance"}})
      if (error.rfind(field + " ", 0) == 0) error = flag + error.substr(field.size());
    return Usage(err, "segment", error);
  }
  const auto rule = ParsePick(args.Get("pick", "largest"));
  if (!rule)
    return Usage(
        err, "segment",
        "--pick expects largest, nearest or a cluster index, got '" + args.Get("pick") + "'");

  const std::string scene_path = args.Get("scene"), out_path = args.Get("out");
  const auto scene = LoadCloud(scene_path, &error);
  if (!scene) {
    err << "saccade segment: " << error << "\n";
    return kExitFailure;
  }
  Segmentation segmentation;
  if (!Segment(*scene, options, &segmentation, &error)) {
    err << "saccade segment: " << scene_path << ": " << error << "\n";
    return kExitFailure;
  }
  const auto picked = Pick(*rule, segmentation, &error);
  if (!picked) {
    err << "saccade segment: " << scene_path << ": " << error << "\n";
    return kExitFailure;
  }
  Cloud model = ExtractPoints(*scene, segmentation.clusters[*picked].indices);
  if (!SaveCloud(out_path, model, &error)) {
    err << "saccade segment: " << error << "\n";
    return kExitFailure;
  }
  if (args.Has("json"))
    out << SegmentationJson(segmentation, *picked, out_path) << "\n";
  else
    PrintSegmentation(segmentation, *picked, out_path, out);
  return kExitOk;
}

}  // namespace saccade
