// The synthetic Kinect: deterministic frames with the Kinect's geometry and noise, and a
// target that is found from a model cut out of another capture.
#include "core/sim/synthetic.h"
#include "core/recognition.h"
#include "core/sim/scenario.h"

#include <gtest/gtest.h>

#include <cmath>

namespace saccade {
namespace {

const CameraIntrinsics kKinect;

std::vector<SceneObject> OneTarget() {
  return {{TargetShape(), PoseOnTable(0.0f, 1.0f, 0.3f, 0.3f), 7}};
}

bool SameCloud(const Cloud& a, const Cloud& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool fa = std::isfinite(a[i].z), fb = std::isfinite(b[i].z);
    if (fa != fb || (fa && a[i].getVector3fMap() != b[i].getVector3fMap())) return false;
  }
  return true;
}

TEST(SyntheticKinect, SameSeedSameFrameOtherSeedOtherNoise) {
  const RenderedFrame a = RenderScene(OneTarget(), 0.3f, kKinect, KinectNoise{}, 5);
  const RenderedFrame b = RenderScene(OneTarget(), 0.3f, kKinect, KinectNoise{}, 5);
  const RenderedFrame c = RenderScene(OneTarget(), 0.3f, kKinect, KinectNoise{}, 6);
  EXPECT_TRUE(SameCloud(a.cloud, b.cloud));
  EXPECT_FALSE(SameCloud(a.cloud, c.cloud));
  EXPECT_EQ(a.cloud.width, 640u);
  EXPECT_EQ(a.cloud.height, 480u);
}

TEST(SyntheticKinect, NoiselessPointsLieOnTheirPixelRayAndOnTheTable) {
  KinectNoise off;
  off.enabled = false;
  const RenderedFrame f = RenderScene({}, 0.3f, kKinect, off, 1);
  int finite = 0;
  for (int v = 0; v < kKinect.height; ++v) {
    for (int u = 0; u < kKinect.width; ++u) {
      const PointT& p = f.cloud.at(u, v);
      if (!std::isfinite(p.z)) continue;
      ++finite;
      ASSERT_NEAR(kKinect.fx * p.x / p.z + kKinect.cx, u, 1e-3);
      ASSERT_NEAR(kKinect.fy * p.y / p.z + kKinect.cy, v, 1e-3);
      ASSERT_NEAR(p.y, 0.3f, 1e-4);  // only the table: y = table height
    }
  }
  // The table is seen below the horizon (v > cy) up to the 4 m range limit, never above it.
  EXPECT_GT(finite, 100000);
  EXPECT_FALSE(std::isfinite(f.cloud.at(320, 100).z));
}

TEST(SyntheticKinect, DepthIsQuantizedInDisparityAndLimitedInRange) {
  const KinectNoise noise;
  const RenderedFrame f = RenderScene(OneTarget(), 0.3f, kKinect, noise, 3);
  int target = 0;
  for (std::size_t i = 0; i < f.cloud.size(); ++i) {
    const float z = f.cloud[i].z;
    if (!std::isfinite(z)) continue;
    ASSERT_GE(z, noise.min_range_m - 1e-3);
    ASSERT_LE(z, noise.max_range_m + 0.02);  // the last disparity step may round outwards
    const double steps = kKinect.fx * noise.baseline_m / z / noise.disparity_step;
    ASSERT_NEAR(steps, std::round(steps), 2e-3 * steps);
    if (f.label[i] == 7) ++target;
  }
  EXPECT_GT(target, 3000);  // the target at 1 m covers thousands of pixels
}

TEST(SyntheticKinect, ProjectorShadowsFallOnTheTableLeftOfAnObject) {
  const std::vector<SceneObject> box = {{Shape{{Shape::Part::Box({0, 0, 0}, {0.05f, 0.1f, 0.05f})}},
                                         PoseOnTable(0.0f, 0.8f, 0.0f, 0.3f, 0.1f), 5}};
  KinectNoise with, without;
  without.projector_shadows = false;
  const RenderedFrame a = RenderScene(box, 0.3f, kKinect, with, 4);
  const RenderedFrame b = RenderScene(box, 0.3f, kKinect, without, 4);
  int lost = 0, lost_right_of_box = 0;
  for (int v = 0; v < kKinect.height; ++v) {
    for (int u = 0; u < kKinect.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * kKinect.width + u;
      const bool shadowed = std::isfinite(b.cloud[i].z) && !std::isfinite(a.cloud[i].z);
      if (!shadowed) continue;
      ++lost;
      EXPECT_EQ(b.label[i], 0u) << "only the background behind the box is shadowed";
      lost_right_of_box += u > kKinect.cx + 0.05 * kKinect.fx / 0.8;
    }
  }
  // The projector is right of the camera, so the shadow is a band at the box's left edge.
  EXPECT_GT(lost, 200);
  EXPECT_EQ(lost_right_of_box, 0);
}

TEST(SyntheticKinect, CutModelIsInTheObjectFrame) {
  const auto objects = OneTarget();
  KinectNoise off;
  off.enabled = false;
  const RenderedFrame f = RenderScene(objects, 0.3f, kKinect, off, 1);
  const Cloud model = CutModel(f, 7, objects[0].pose);
  ASSERT_GT(model.size(), 3000u);
  for (const auto& p : model) {  // inside the target's 14 x 15 x 10 cm bounds, own frame
    EXPECT_LE(p.getVector3fMap().cwiseAbs().maxCoeff(), 0.101f);
    EXPECT_LE(p.y, 0.0501f);  // nothing below its bottom face
  }
}

// The demo's case, over several seeds: a model cut from one capture, found in another capture
// where the target moved and turned among clutter. Foveated, the one instance lies on the
// truth; plain over the whole frame, the best one does, and with `plain_only_one` it is alone.
void ExpectTargetFoundAcrossCaptures(const RecognitionOptions& options, bool plain_only_one) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const CrossCaptureCase c = MakeDemoCase(seed, kKinect);
    std::string error;
    const auto model = DescribeModel(c.model, options, &error);
    ASSERT_TRUE(model) << error;
    const Eigen::Vector3f centre = c.truth * model->centroid();
    for (bool foveated : {true, false}) {
      SCOPED_TRACE(foveated ? "foveated" : "plain");
      SceneQuery query;
      query.intrinsics = kKinect;
      query.foveated = foveated;
      query.fovea_m = centre + Eigen::Vector3f(0.05f, -0.03f, 0.04f);
      const RecognitionResult r = Recognize(*model, c.scene.cloud, query, options);
      ASSERT_GE(r.instances.size(), 1u);
      if (foveated || plain_only_one) {
        EXPECT_EQ(r.instances.size(), 1u);
      }
      const PoseError e =
          ComparePoses(r.instances[0].model_to_scene, c.truth.matrix(), model->centroid());
      EXPECT_LT(e.translation_m, 0.01);
      EXPECT_LT(e.rotation_deg, 3.0);
    }
  }
}

// Hand-set cross-capture radii.
TEST(SyntheticRecognition, TargetFoundAcrossCapturesFoveatedAndPlain) {
  ExpectTargetFoundAcrossCaptures(RecognitionOptions::CrossCapture(), true);
}

// Saccade's defaults (radii fitted to the model): in this colourless frame plain search over
// the whole frame may also keep instances elsewhere, which verification cannot tell apart.
TEST(SyntheticRecognition, TargetFoundAcrossCapturesWithTheDefaults) {
  ExpectTargetFoundAcrossCaptures(RecognitionOptions{}, false);
}

}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

// A value far beyond a room (a table 1e30 m below, a target at 1e30 m/s) once sent the renderer
// into a loop over billions of pixels that no signal ended: refused when the scenario is read,
// and a pose at infinity, if one still reaches the renderer, is seen by no pixel.
TEST(Scenario, ValuesBeyondARoomAreRefusedAndNeverRendered) {
  const Scenario demo = *ScenarioPreset("occluded");
  std::string error;
  ASSERT_TRUE(demo.IsValid(&error)) << error;
  const auto refused = [&](const char* what, auto change) {
    Scenario s = demo;
    change(&s);
    EXPECT_FALSE(s.IsValid(&error)) << what;
    EXPECT_NE(error.find("100"), std::string::npos) << what << ": " << error;
  };
  refused("table", [](Scenario* s) { s->table_height_m = 1e30f; });
  refused("speed", [](Scenario* s) { s->target_motion.velocity_xz_mps.x() = 1e30f; });
  refused("start", [](Scenario* s) { s->target_motion.start_xz_m.y() = -1e6f; });
  refused("turn", [](Scenario* s) { s->camera_motion.yaw_rate_radps = INFINITY; });
  refused("nan", [](Scenario* s) { s->target_motion.radius_m = NAN; });

  Scenario far = demo;
  far.target_motion.kind = Trajectory::Kind::kLinear;
  far.target_motion.velocity_xz_mps = Eigen::Vector2f(1e30f, 0.0f);  // past IsValid, on purpose
  const ScenarioFrame f = RenderScenarioFrame(far, 20, CameraIntrinsics{});
  EXPECT_EQ(f.truth.visible_fraction, 0.0f);
}

}  // namespace
}  // namespace saccade
