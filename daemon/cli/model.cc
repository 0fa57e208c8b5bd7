// saccade model: make a model from what a user has: a mesh (CAD, a scan, a Blender export),
// rendered from all around it into the whole surface (core/mesh.h), or captures of the object
// from several sides, aligned into one model of several views (core/view_alignment.h). The model
// it writes is a PCD file any command takes where it takes a model.
#include "core/model.h"
#include "core/fail.h"
#include "core/foveation.h"
#include "core/mesh.h"
#include "core/pictures/overlay.h"
#include "core/segmentation.h"
#include "core/sim/scenario.h"
#include "core/sim/synthetic.h"
#include "core/view_alignment.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/cli/pick.h"
#include "daemon/cli/progress.h"
#include "daemon/eval/overlays.h"
#include "daemon/tbb_parallel.h"
#include "io/base/json.h"
#include "io/formats/cloud_io.h"
#include "io/formats/mesh_io.h"
#include "io/sources/model_source.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <ostream>

namespace saccade {
namespace {

// The object's points in capture `path`, organized (the rest NaN): by its mOSD label when
// `object` > 0, else the cluster `pick` chooses among those `saccade segment` finds.
std::optional<Cloud> CutCapture(const std::string& path, int object, const PickRule& pick,
                                std::string* error) {
  std::vector<int> points;
  Cloud cloud;
  if (object > 0) {
    auto labelled = LoadLabelledCloud(path, error);
    if (!labelled) return std::nullopt;
    cloud = std::move(labelled->cloud);
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (labelled->labels[i] >= 10 && int(labelled->labels[i] / 10) == object &&
          FinitePoint(cloud[i]))
        points.push_back(int(i));
    if (points.empty()) {
      Fail(error, path + ": no point labelled as object " + std::to_string(object));
      return std::nullopt;
    }
  } else {
    auto loaded = LoadCloud(path, error);
    if (!loaded) return std::nullopt;
    cloud = std::move(*loaded);
    Segmentation s;
    if (!Segment(cloud, SegmentationOptions{}, &s, error)) {
      *error = path + ": " + *error;
      return std::nullopt;
    }
    const auto picked = Pick(pick, s, error);
    if (!picked) {
      *error = path + ": " + *error;
      return std::nullopt;
    }
    points = s.clusters[*picked].indices;
  }
  std::vector<std::uint8_t> keep(cloud.size(), 0);
  for (int i : points) keep[std::size_t(i)] = 1;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!keep[i]) cloud[i].x = cloud[i].y = cloud[i].z = nan;
  return cloud;
}

int ModelFromCaptures(const Args& args, std::ostream& out, std::ostream& err) {
  const std::vector<std::string> paths = Args::ParseList(args.Get("captures"));
  if (paths.size() < 2) return Usage(err, "model", "--captures expects two or more PCD files");
  std::vector<int> objects;
  for (const std::string& k : Args::ParseList(args.Get("object"))) {
    const auto v = Args::ParsePositiveInt(k);
    if (!v) return Usage(err, "model", "--object expects positive object numbers");
    objects.push_back(*v);
  }
  if (!objects.empty() && objects.size() != 1 && objects.size() != paths.size())
    return Usage(err, "model", "--object expects one number, or one per capture");
  if (!objects.empty() && args.Has("pick"))
    return Usage(err, "model", "--object and --pick are exclusive");
  const auto pick = ParsePick(args.Get("pick", "largest"));
  if (!pick) return Usage(err, "model", "--pick expects largest, nearest or a cluster index");

  std::string error;
  std::vector<Cloud> cuts;
  ProgressLine progress(err, ProgressLine::StderrIsATerminal());  // on a terminal only
  for (std::size_t i = 0; i < paths.size(); ++i) {
    progress.Show("saccade model: captures cut", i, paths.size());
    const int object = objects.empty() ? 0 : objects[objects.size() == 1 ? 0 : i];
    auto cut = CutCapture(paths[i], object, *pick, &error);
    if (!cut) {
      err << "saccade model: " << error << "\n";
      return kExitFailure;
    }
    cuts.push_back(std::move(*cut));
  }
  progress.Show("saccade model: captures cut", paths.size(), paths.size());
  progress.Clear();
  std::vector<const Cloud*> captures;
  for (const Cloud& c : cuts) captures.push_back(&c);
  const AlignmentOptions options;
  const auto pairs = AlignAll(captures, options, MakeTbbParallelFor());
  std::vector<int> parent;
  const auto poses = ChainViews(pairs, captures, std::vector<bool>(paths.size(), true), 0, &parent);
  for (std::size_t i = 1; i < paths.size(); ++i) {
    if (poses[i]) continue;
    // The nearest miss, to say how far from fitting it was.
    float overlap = 0;
    for (std::size_t j = 0; j < paths.size(); ++j)
      if (j != i) overlap = std::max({overlap, pairs[i][j].overlap, pairs[j][i].overlap});
    err << "saccade model: " << paths[i] << ": fits none of the other captures (best overlap "
        << int(std::lround(100 * overlap)) << "%, " << int(std::lround(100 * options.min_overlap))
        << "% needed, with at most " << int(std::lround(100 * options.max_seen_through))
        << "% of it where another capture saw through): is it the same object, seen from a side "
           "another capture shares?\n";
    return kExitFailure;
  }
  const float disagreement = LoopDisagreement(pairs, poses, captures);
  const std::vector<Cloud> views = PlaceViews(captures, poses);
  const std::string out_path = args.Get("out");
  if (!SaveModelViews(out_path, views, &error)) {
    err << "saccade model: " << error << "\n";
    return kExitFailure;
  }
  const Cloud all = MergeViews(views);
  const Eigen::Vector3f size = BoundingBox(all)->Size();
  // The alignment that joined capture i to its parent in the chain: of the two directions, the
  // found one of more overlap.
  const auto joined = [&](std::size_t i) -> const ViewAlignment& {
    const std::size_t p = std::size_t(parent[i]);
    return pairs[i][p].found && (!pairs[p][i].found || pairs[i][p].overlap >= pairs[p][i].overlap)
               ? pairs[i][p]
               : pairs[p][i];
  };
  if (args.Has("json")) {
    JsonWriter j;
    j.BeginObject().Key("model").Value(out_path).Key("points").Value(all.size());
    j.Key("size_m").Vector3(size).Key("views").Value(views.size());
    j.Key("loop_disagreement_m").Value(double(disagreement)).Key("captures").BeginArray();
    for (std::size_t i = 0; i < paths.size(); ++i) {
      j.BeginObject().Key("capture").Value(paths[i]).Key("points").Value(CountFinite(cuts[i]));
      if (parent[i] >= 0) {
        const std::size_t p = std::size_t(parent[i]);
        const ViewAlignment& a = joined(i);
        j.Key("joined_to").Value(paths[p]).Key("overlap").Value(double(a.overlap));
        j.Key("rmse_m").Value(double(a.rmse_m)).Key("seen_through").Value(double(a.seen_through));
        j.Key("colour_agreement").Value(double(a.colour));
      }
      j.EndObject();
    }
    j.EndArray().EndObject();
    out << j.str() << "\n";
    return kExitOk;
  }
  out << std::fixed << std::setprecision(3);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    out << paths[i] << ": " << CountFinite(cuts[i]) << " points";
    if (parent[i] < 0) {
      out << ", the model's frame (its camera's)\n";
      continue;
    }
    const std::size_t p = std::size_t(parent[i]);
    const ViewAlignment& a = joined(i);
    out << ", joined to " << paths[p] << ": " << int(std::lround(100 * a.overlap)) << "% overlap, "
        << 1000 * a.rmse_m << " mm RMS, " << int(std::lround(100 * a.seen_through))
        << "% seen through";
    if (a.colour >= 0) out << ", colours agree " << a.colour;
    out << "\n";
  }
  out << "wrote " << out_path << ": " << all.size() << " points, " << size.x() << " x " << size.y()
      << " x " << size.z() << " m, " << views.size()
      << " views; alignments outside the chain agree with it within " << 100 * disagreement
      << " cm\n";
  return kExitOk;
}

// The synthetic Kinect's objects as the meshes a user with their CAD would have: the target
// (the demo's) and the paper protocol's ball, in their own frames.
int ExportSynthetic(const Args& args, std::ostream& out, std::ostream& err) {
  const std::string name = args.Get("synthetic");
  const std::string preset = name == "target" ? "static" : name == "ball" ? "paper-protocol" : "";
  if (preset.empty())
    return Usage(err, "model",
                 "--synthetic expects target or ball, got '" + name.substr(0, 40) + "'");
  const Mesh mesh = ShapeMesh(ScenarioPreset(preset)->target);
  std::string error;
  const std::string path = args.Get("out");
  if (!SaveMeshPly(path, mesh, &error)) {
    err << "saccade model: " << error << "\n";
    return kExitFailure;
  }
  out << "wrote " << path << ": the synthetic " << name << ", " << mesh.vertices.size()
      << " vertices, " << mesh.triangles.size() << " triangles (metres, its own frame)\n";
  return kExitOk;
}

int ModelFromMesh(const Args& args, std::ostream& out, std::ostream& err) {
  const std::string unit = args.Get("unit", "m");
  if (unit != "m" && unit != "mm")
    return Usage(err, "model", "--unit expects m or mm, got '" + unit.substr(0, 40) + "'");
  MeshViewOptions options;
  if (args.Has("views")) {
    const auto v = Args::ParsePositiveInt(args.Get("views"));
    if (!v) return Usage(err, "model", "--views expects a positive integer");
    options.views = *v;
  }
  for (auto [flag, field] : {std::pair<const char*, float*>{"distance", &options.distance_m},
                             {"spacing", &options.spacing_m}}) {
    if (!args.Has(flag)) continue;
    const auto v = Args::ParseNumber(args.Get(flag));
    if (!v) return Usage(err, "model", std::string("--") + flag + " expects a number");
    *field = static_cast<float>(*v);
  }
  std::string error;
  if (!options.IsValid(&error)) return Usage(err, "model", "--" + error);

  const std::string mesh_path = args.Get("mesh"), out_path = args.Get("out");
  const auto mesh = LoadMesh(mesh_path, unit == "mm" ? 0.001f : 1.0f, &error);
  if (!mesh) {
    err << "saccade model: " << error << "\n";
    return kExitFailure;
  }
  const MeshModel model = RenderMeshModel(*mesh, options);
  if (model.points.empty()) {
    err << "saccade model: " << mesh_path << ": no view saw any of the mesh\n";
    return kExitFailure;
  }
  if (!SaveCloud(out_path, model.points, &error)) {
    err << "saccade model: " << error << "\n";
    return kExitFailure;
  }
  const Box box = *BoundingBox(model.points);
  const Eigen::Vector3f size = box.Size();
  std::vector<int> seen = model.points_per_view;
  std::sort(seen.begin(), seen.end());
  if (args.Has("json")) {
    JsonWriter j;
    j.BeginObject()
        .Key("model")
        .Value(out_path)
        .Key("mesh")
        .Value(mesh_path)
        .Key("triangles")
        .Value(mesh->triangles.size())
        .Key("points")
        .Value(model.points.size())
        .Key("size_m")
        .Vector3(size)
        .Key("views")
        .Value(int(seen.size()))
        .Key("view_points_min")
        .Value(seen.front())
        .Key("view_points_median")
        .Value(seen[seen.size() / 2])
        .Key("view_points_max")
        .Value(seen.back())
        .EndObject();
    out << j.str() << "\n";
  } else {
    out << std::fixed << std::setprecision(3) << "wrote " << out_path << ": " << model.points.size()
        << " points, " << size.x() << " x " << size.y() << " x " << size.z() << " m, from "
        << seen.size() << " views of " << mesh->triangles.size() << " triangles (each view saw "
        << seen.front() << "-" << seen.back() << " pixels of it, median " << seen[seen.size() / 2]
        << ")\n";
  }
  return kExitOk;
}

// Draws the model in `model_path` from four sides into `png_path`.
int DrawModel(const std::string& model_path, const std::string& png_path, bool quiet,
              std::ostream& out, std::ostream& err) {
  std::string error;
  const auto views = LoadModelViews(model_path, &error);
  if (!views) {
    err << "saccade model: " << error << "\n";
    return kExitFailure;
  }
  // Seen first from where its camera stood: a capture's, or the first capture's (the frame of
  // a model of captures); a mesh's model has its origin inside and is seen from -z.
  Cloud model = MergeViews(*views);
  model.sensor_origin_ = (*views)[0].sensor_origin_;
  if (!WriteOverlayPng(png_path, ModelImage(model, 4, 320), &error)) {
    err << "saccade model: " << error << "\n";
    return kExitFailure;
  }
  if (!quiet) out << "drew " << model_path << " to " << png_path << "\n";
  return kExitOk;
}

}  // namespace

int RunModel(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade model",
            "Makes a model from a mesh: renders it, z-buffered, from --views viewpoints all "
            "around it with the sensor's intrinsics (a Kinect's, 640x480 at 525 px), keeps one "
            "point per --spacing cube of what any view saw, with its colour (per face from an "
            "OBJ's materials, per vertex from a PLY), and writes the whole surface in the mesh's "
            "frame: poses found with it are the mesh's pose in the camera frame.");
  const MeshViewOptions defaults;
  args.Value("mesh", "FILE", "the mesh: .obj (with its .mtl), .ply or .stl")
      .Value("captures", "A.pcd,B.pcd,...",
             "instead of a mesh: captures of the object from several sides, aligned into one "
             "model in the first capture's camera frame (each a view: where it was seen from "
             "is kept)")
      .Value("synthetic", "target|ball",
             "instead: write the synthetic Kinect's object as a mesh (PLY, metres, its own "
             "frame) to --out, for other tools or `--mesh`")
      .Value("object", "K[,K...]",
             "with --captures: the object's mOSD label number, one for all or one per capture")
      .Value("pick", "RULE",
             "with --captures and no --object: the cluster `saccade segment` would pick "
             "(largest, nearest or an index; default: largest)")
      .Value("out", "MODEL.pcd", "the model to write (required)")
      .Value("unit", "m|mm", "the mesh's unit (default: m)")
      .Value("views", "N", "viewpoints around the mesh" + Args::Default(defaults.views))
      .Value("distance", "M",
             "from the mesh's centre to each viewpoint, metres (farther when the mesh would not "
             "fit the image)" +
                 Args::Default(defaults.distance_m))
      .Value("spacing", "M",
             "one point per cube of this edge, metres" + Args::Default(defaults.spacing_m))
      .Value("show", "M.pcd",
             "instead: draw a model already made (a capture's cut, a mesh's, captures') to "
             "--render, nothing written")
      .Value("render", "OUT.png",
             "also draw the model from four sides, 90 degrees apart (the first from where a "
             "captured model's camera stood), as a PNG")
      .Switch("json", "print one JSON object instead of text");
  if (auto code = args.Parse(argv, out, err)) return *code;
  const int sources = int(args.Has("mesh")) + int(args.Has("captures")) +
                      int(args.Has("synthetic")) + int(args.Has("show"));
  if (sources != 1)
    return Usage(err, "model", "expects one of --mesh, --captures, --synthetic and --show");
  if (args.Has("show") && !args.Has("render"))
    return Usage(err, "model", "--show draws the model: give --render OUT.png");
  if (!args.Has("show") && !args.Has("out")) return Usage(err, "model", "missing --out");
  if (args.Has("render") && args.Has("synthetic"))
    return Usage(err, "model", "--synthetic writes a mesh, not a model: nothing to --render");
  if (args.Has("render"))
    if (auto code = CheckPngPath(args.Get("render"), "model", err)) return *code;
  int code = kExitOk;
  if (args.Has("captures"))
    code = ModelFromCaptures(args, out, err);
  else if (args.Has("synthetic"))
    code = ExportSynthetic(args, out, err);
  else if (args.Has("mesh"))
    code = ModelFromMesh(args, out, err);
  if (code != kExitOk || !args.Has("render")) return code;
  return DrawModel(args.Has("show") ? args.Get("show") : args.Get("out"), args.Get("render"),
                   args.Has("json"), out, err);
}

}  // namespace saccade
