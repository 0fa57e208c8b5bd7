// saccade model: make a model from what a user has. Today a mesh (CAD, a scan, a Blender
// export), rendered from all around it into the whole surface (core/mesh.h); the model it writes
// is a PCD file any command takes where it takes a model.
#include "core/fail.h"
#include "core/foveation.h"
#include "core/mesh.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "io/cloud_io.h"
#include "io/json.h"
#include "io/mesh_io.h"

#include <algorithm>
#include <iomanip>
#include <ostream>

namespace saccade {

int RunModel(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade model",
            "Makes a model from a mesh: renders it, z-buffered, from --views viewpoints all "
            "around it with the sensor's intrinsics (a Kinect's, 640x480 at 525 px), keeps one "
            "point per --spacing cube of what any view saw, with its colour (per face from an "
            "OBJ's materials, per vertex from a PLY), and writes the whole surface in the mesh's "
            "frame: poses found with it are the mesh's pose in the camera frame.");
  const MeshViewOptions defaults;
  args.Value("mesh", "FILE", "the mesh: .obj (with its .mtl), .ply or .stl (required)")
      .Value("out", "MODEL.pcd", "the model to write (required)")
      .Value("unit", "m|mm", "the mesh's unit (default: m)")
      .Value("views", "N", "viewpoints around the mesh" + Args::Default(defaults.views))
      .Value("distance", "M",
             "from the mesh's centre to each viewpoint, metres (farther when the mesh would not "
             "fit the image)" +
                 Args::Default(defaults.distance_m))
      .Value("spacing", "M",
             "one point per cube of this edge, metres" + Args::Default(defaults.spacing_m))
      .Switch("json", "print one JSON object instead of text");
  if (auto code = args.Parse(argv, out, err)) return *code;
  for (const char* required : {"mesh", "out"})
    if (!args.Has(required)) return Usage(err, "model", std::string("missing --") + required);
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

}  // namespace saccade
