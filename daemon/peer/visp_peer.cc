// saccade-visp-peer: ViSP's model-based tracker (vpMbGenericTracker, dense depth features, from
// Debian's libvisp-mbt-dev) on the same frames as `saccade bench-track`, started at the truth's
// first pose, scored the same way: the CPU peer Saccade's tracker is compared with
// (docs/BENCHMARKS.md). A benchmark program only: saccaded does not depend on it.
#include "core/eval/pose_scoring.h"
#include "daemon/args.h"
#include "daemon/exit_codes.h"
#include "io/base/json.h"
#include "io/formats/mesh_io.h"
#include "io/formats/truth_file.h"
#include "io/sources/frame_source.h"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/mbt/vpMbGenericTracker.h>

#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace saccade {
namespace {

// The mesh as ViSP's CAO model: its vertices and its triangles as faces.
bool WriteCao(const Mesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out << "V1\n# 3D points\n" << mesh.vertices.size() << "\n";
  for (const Eigen::Vector3f& v : mesh.vertices)
    out << v.x() << " " << v.y() << " " << v.z() << "\n";
  out << "# 3D lines\n0\n# Faces from 3D lines\n0\n# Faces from 3D points\n"
      << mesh.triangles.size() << "\n";
  for (const auto& t : mesh.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  out << "# 3D cylinders\n0\n# 3D circles\n0\n";
  return bool(out);
}

vpHomogeneousMatrix ToVisp(const Eigen::Matrix4f& m) {
  vpHomogeneousMatrix out;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) out[r][c] = m(int(r), int(c));
  return out;
}

Eigen::Matrix4f FromVisp(const vpHomogeneousMatrix& m) {
  Eigen::Matrix4f out;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) out(int(r), int(c)) = float(m[r][c]);
  return out;
}

int Run(int argc, char** argv) {
  Args args("saccade-visp-peer",
            "ViSP's model-based tracker (dense depth) on a sequence, started at its truth's first "
            "pose and scored against the truth as saccade bench-track scores Saccade. The last "
            "line is one JSON object.");
  args.Value("source", "SPEC", "the frames (saccade record --help) (required)")
      .Value("mesh", "FILE.obj|.ply|.stl", "the object's mesh, in metres (required)")
      .Value("truth", "FILE.csv", "its pose per frame (frame,T00..T33) (required)")
      .Value("name", "NAME", "the sequence's name in the report (default: the source)")
      .Value("tolerance-cm", "C", "a frame is tracked within C centimetres (default: 2)")
      .Value("tolerance-deg", "D", "... and D degrees of the truth (default: 5)")
      .Value("symmetry", "cube", "the object looks the same turned onto any of its frame's axes");
  std::vector<std::string> argv_list(argv + 1, argv + argc);
  if (auto code = args.Parse(argv_list, std::cout, std::cerr)) return *code;
  if (!args.Has("source") || !args.Has("mesh") || !args.Has("truth")) {
    std::cerr << "saccade-visp-peer: --source, --mesh and --truth are required\n";
    return kExitUsage;
  }
  if (args.Has("symmetry") && args.Get("symmetry") != "cube") {
    std::cerr << "saccade-visp-peer: --symmetry knows cube only\n";
    return kExitUsage;
  }
  const double tol_cm = Args::ParseNumber(args.Get("tolerance-cm", "2")).value_or(-1);
  const double tol_deg = Args::ParseNumber(args.Get("tolerance-deg", "5")).value_or(-1);
  if (!(tol_cm > 0) || !(tol_deg > 0)) {
    std::cerr << "saccade-visp-peer: --tolerance-cm and --tolerance-deg expect numbers > 0\n";
    return kExitUsage;
  }
  std::string error;
  std::map<int, Eigen::Isometry3f> truth;
  const std::optional<Mesh> mesh = LoadMesh(args.Get("mesh"), 1.0f, &error);
  if (!mesh || !ReadPoseTable(args.Get("truth"), &truth, &error)) {
    std::cerr << "saccade-visp-peer: " << error << "\n";
    return kExitFailure;
  }
  if (!truth.count(0)) {
    std::cerr << "saccade-visp-peer: " << args.Get("truth") << ": no pose for frame 0\n";
    return kExitFailure;
  }
  const std::string cao = (std::filesystem::temp_directory_path() /
                           ("saccade-visp-peer-" + std::to_string(getpid()) + ".cao"))
                              .string();
  if (!WriteCao(*mesh, cao)) {
    std::cerr << "saccade-visp-peer: cannot write " << cao << "\n";
    return kExitFailure;
  }
  std::unique_ptr<FrameSource> source = OpenSource(args.Get("source"), &error);
  if (!source) {
    std::cerr << "saccade-visp-peer: " << error << "\n";
    return kExitFailure;
  }
  std::vector<Eigen::Matrix4f> turns{Eigen::Matrix4f::Identity()};
  if (args.Has("symmetry")) turns = CubeRotations();

  vpMbGenericTracker tracker(1, vpMbGenericTracker::DEPTH_DENSE_TRACKER);
  bool started = false;
  const std::vector<std::string> names = tracker.getCameraNames();
  std::vector<double> error_cm, error_deg, step_cm, step_deg, ms;
  int frames = 0, scored = 0, within = 0, failed = 0;
  Eigen::Matrix4f last_pose, last_truth;
  bool have_last = false;
  Frame frame;
  for (int i = 0;; ++i) {
    const FrameSource::Status st = source->Next(&frame, &error);
    if (st == FrameSource::Status::kError) {
      std::cerr << "saccade-visp-peer: " << error << "\n";
      std::remove(cao.c_str());
      return kExitFailure;
    }
    if (st != FrameSource::Status::kFrame) break;
    ++frames;
    const CameraIntrinsics& k = frame.intrinsics;
    const Cloud& cloud = *frame.cloud;
    vpImage<unsigned char> image(unsigned(k.height), unsigned(k.width), 0);
    std::vector<vpColVector> points(cloud.size(), vpColVector(3, 0.0));
    for (std::size_t p = 0; p < cloud.size(); ++p)
      if (FinitePoint(cloud[p])) {
        points[p][0] = cloud[p].x;
        points[p][1] = cloud[p].y;
        points[p][2] = cloud[p].z;
      }
    std::map<std::string, const vpImage<unsigned char>*> images{{names[0], &image}};
    std::map<std::string, const std::vector<vpColVector>*> clouds{{names[0], &points}};
    std::map<std::string, unsigned> widths{{names[0], unsigned(k.width)}},
        heights{{names[0], unsigned(k.height)}};
    if (!started) {
      tracker.setCameraParameters(vpCameraParameters(k.fx, k.fy, k.cx, k.cy));
      tracker.loadModel(cao);
      tracker.initFromPose(image, ToVisp(truth.at(0).matrix()));
      started = true;
    }
    const auto t0 = std::chrono::steady_clock::now();
    try {
      tracker.track(images, clouds, widths, heights);
    } catch (const vpException&) {
      ++failed;  // kept at its last pose, as the tracker leaves it
    }
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    vpHomogeneousMatrix cMo;
    tracker.getPose(cMo);
    const auto row = truth.find(i);
    if (row == truth.end()) {
      have_last = false;
      continue;
    }
    const Eigen::Matrix4f pose = FromVisp(cMo), true_pose = row->second.matrix();
    const PoseError e =
        LeastError(pose, true_pose, Eigen::Matrix4f::Identity(), Eigen::Vector3f::Zero(), turns);
    ++scored;
    error_cm.push_back(100 * e.translation_m);
    error_deg.push_back(e.rotation_deg);
    if (100 * e.translation_m <= tol_cm && e.rotation_deg <= tol_deg) ++within;
    if (have_last) {
      const PoseError s =
          StepError(last_pose, pose, last_truth, true_pose, Eigen::Vector3f::Zero());
      step_cm.push_back(100 * s.translation_m);
      step_deg.push_back(s.rotation_deg);
    }
    last_pose = pose, last_truth = true_pose, have_last = true;
  }
  std::remove(cao.c_str());
  const std::string name = args.Get("name", args.Get("source"));
  std::printf(
      "%s (ViSP dense depth): %d/%d frames within %.0f cm and %.0f deg, error p50 %.2f "
      "cm %.1f deg, %d failed steps; track p50 %.1f ms\n",
      name.c_str(), within, scored, tol_cm, tol_deg, Quantile(error_cm, 0.5),
      Quantile(error_deg, 0.5), failed, Quantile(ms, 0.5));
  JsonWriter j;
  j.BeginObject()
      .Key("sequence")
      .Value(name)
      .Key("tracker")
      .Value(std::string("visp-mbt-dense-depth"));
  j.Key("frames").Value(frames).Key("scored_frames").Value(scored);
  j.Key("tracked_frames").Value(within).Key("failed_steps").Value(failed);
  j.Key("error_cm_p50").Value(Quantile(error_cm, 0.5));
  j.Key("error_cm_p90").Value(Quantile(error_cm, 0.9));
  j.Key("error_deg_p50").Value(Quantile(error_deg, 0.5));
  j.Key("error_deg_p90").Value(Quantile(error_deg, 0.9));
  j.Key("step_error_cm_p50").Value(Quantile(step_cm, 0.5));
  j.Key("step_error_cm_p90").Value(Quantile(step_cm, 0.9));
  j.Key("step_error_deg_p50").Value(Quantile(step_deg, 0.5));
  j.Key("step_error_deg_p90").Value(Quantile(step_deg, 0.9));
  j.Key("track_ms_p50").Value(Quantile(ms, 0.5)).Key("track_ms_p90").Value(Quantile(ms, 0.9));
  j.EndObject();
  std::printf("%s\n", j.str().c_str());
  return kExitOk;
}

}  // namespace
}  // namespace saccade

int main(int argc, char** argv) { return saccade::Run(argc, argv); }
