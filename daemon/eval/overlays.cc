#include "daemon/eval/overlays.h"

#include "core/eval/evaluation.h"
#include "io/formats/images.h"

#include <cctype>
#include <sstream>
#include <system_error>

namespace saccade {
namespace {

constexpr float kRuleM = 0.08f;  // the paper's rule: a detection within 8 cm is the object
constexpr std::size_t kLabelledInstances = 12;  // instances labelled in a case's image, by rank

std::vector<Eigen::Vector3f> FinitePoints(const Cloud& cloud) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(cloud.size());
  for (const PointT& p : cloud.points)
    if (FinitePoint(p)) out.push_back(p.getVector3fMap());
  return out;
}

// A case or configuration name as part of a file name: anything but letters, digits, '.', '-'
// and '_' becomes '_'.
std::string FileSafe(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return out;
}

}  // namespace

std::string InstanceLabel(std::size_t index, const Detection& d) {
  std::ostringstream s;
  s << '#' << index << ' ';
  if (d.confidence >= 0) {
    s.setf(std::ios::fixed);
    s.precision(2);
    s << d.confidence;
  } else {
    s << d.votes << " VOTES";
  }
  return s.str();
}

RgbCanvas RenderOverlay(const Cloud& scene, const CameraIntrinsics& camera, const Cloud& model,
                        const std::vector<OverlayMark>& marks) {
  RgbCanvas canvas = SceneImage(scene, camera);
  const std::vector<Eigen::Vector3f> points_M = FinitePoints(model);
  DrawMarks(points_M, FitOrientedBox(points_M), marks, camera, &canvas);
  return canvas;
}

bool WriteOverlayPng(const std::string& path, const RgbCanvas& canvas, std::string* error) {
  RgbImage image;
  image.width = canvas.width;
  image.height = canvas.height;
  image.channels = 3;
  image.data = canvas.data;
  if (WriteRgbPng(path, image, error)) return true;
  std::error_code ec;  // libpng removes what it began; a file it could not remove goes here
  std::filesystem::remove(path, ec);
  return false;
}

namespace eval {

int WriteCaseOverlays(const std::vector<EvalConfiguration>& configs,
                      const std::vector<EvalModel>& models, const std::vector<Scene>& scenes,
                      const std::vector<std::vector<Trial>>& trials,
                      const std::filesystem::path& dir, std::string* error) {
  const std::filesystem::path folder = dir / "overlays";
  int written = 0;
  for (std::size_t c = 0; c < configs.size(); ++c)
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      const Scene& s = scenes[i];
      const Trial& t = trials[c][i];
      const SceneScore score = ScoreScene(t.centres, s.truth_m, kRuleM);
      const bool missed = s.feasible && score.true_positives == 0;
      if (!missed && score.false_positives == 0) continue;
      if (written == 0) {
        std::error_code ec;
        std::filesystem::create_directories(folder, ec);
        if (ec) {
          *error = folder.string() + ": cannot create it (" + ec.message() + ")";
          return -1;
        }
      }
      // Drawn bottom to top: false instances (the best ranked on top), true ones, the truth;
      // only the best ranked are labelled, so that a hundred false instances stay legible.
      std::vector<OverlayMark> marks, true_marks;
      for (std::size_t k = t.instances.size(); k-- > 0;) {
        const bool true_instance = (t.centres[k] - s.truth_m).norm() <= kRuleM;
        (true_instance ? true_marks : marks)
            .push_back({t.instances[k].model_to_scene, true_instance ? kTrueColour : kFalseColour,
                        k < kLabelledInstances ? InstanceLabel(k, t.instances[k]) : ""});
      }
      marks.insert(marks.end(), true_marks.begin(), true_marks.end());
      if (s.truth_pose) marks.push_back({*s.truth_pose, kTruthColour, "TRUTH"});
      const CameraIntrinsics& camera = s.frame.intrinsics;
      RgbCanvas canvas = RenderOverlay(*s.frame.cloud, camera, models[s.model].cloud, marks);
      if (!s.truth_pose && s.truth_m.z() > 0) {  // a cross at the true centre
        const Eigen::Vector2d uv = camera.Project(s.truth_m);
        DrawLine(uv - Eigen::Vector2d(8, 8), uv + Eigen::Vector2d(8, 8), kTruthColour, 3, &canvas);
        DrawLine(uv - Eigen::Vector2d(8, -8), uv + Eigen::Vector2d(8, -8), kTruthColour, 3,
                 &canvas);
      }
      // What went wrong, at the top left: "CASE / CONFIG: MISSED, 2 FALSE".
      std::string heading = s.name + " / " + configs[c].name + ":";
      if (missed) heading += " MISSED";
      if (missed && score.false_positives) heading += ",";
      if (score.false_positives) heading += " " + std::to_string(score.false_positives) + " FALSE";
      const int scale = TextSize(heading, 2).x() + 12 <= canvas.width ? 2 : 1;
      DrawText(heading, 6, 6, scale, Rgb{255, 255, 255}, Rgb{0, 0, 0}, &canvas);
      const std::string file = FileSafe(s.name) + "-" + FileSafe(configs[c].name) + ".png";
      if (!WriteOverlayPng((folder / file).string(), canvas, error)) return -1;
      ++written;
    }
  return written;
}

}  // namespace eval
}  // namespace saccade
