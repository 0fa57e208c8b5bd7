// Models from meshes (core/mesh.h): the rendering's geometry on a box, and the synthetic Kinect's
// target found in its demo scene by a model made from its mesh alone, against the true pose.
#include "core/mesh.h"

#include "core/recognition.h"
#include "core/sim/scenario.h"
#include "core/sim/synthetic.h"
#include "core/surface_views.h"
#include "core/verification.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace saccade {
namespace {

TEST(RenderMeshModel, GivesTheWholeSurfaceOfABoxWithNormalsFacingOut) {
  Shape box;
  box.parts.push_back(Shape::Part::Box({0.01f, 0, 0}, {0.05f, 0.03f, 0.02f}));
  const Mesh mesh = ShapeMesh(box);
  ASSERT_TRUE(IsValidMesh(mesh, nullptr));
  MeshViewOptions o;
  o.spacing_m = 0.002f;
  const MeshModel m = RenderMeshModel(mesh, o);
  ASSERT_EQ(m.points.size(), m.normals.size());
  EXPECT_EQ(m.points_per_view.size(), std::size_t(o.views));
  int faces_seen[6] = {};
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const Eigen::Vector3f d = m.points[i].getVector3fMap() - Eigen::Vector3f(0.01f, 0, 0);
    const Eigen::Vector3f half(0.05f, 0.03f, 0.02f);
    // On the surface: on one face's plane (within 1 mm), inside the others' extent.
    const Eigen::Vector3f gap = (d.cwiseAbs() - half).cwiseAbs();
    int axis;
    ASSERT_LT(gap.minCoeff(&axis), 0.001f) << "point " << i << " is off the surface";
    ASSERT_TRUE(((d.cwiseAbs() - half).array() < 0.001f).all()) << "point " << i;
    ++faces_seen[2 * axis + (d[axis] > 0)];
    EXPECT_GT(m.normals[i].dot(d), 0) << "point " << i << ": normal faces in";
    EXPECT_EQ(m.points[i].r, 200);
  }
  for (int f = 0; f < 6; ++f) EXPECT_GT(faces_seen[f], 100) << "face " << f;
  // One point per 2 mm cube: about the surface's area over the spacing squared.
  const float area = 2 * (0.1f * 0.06f + 0.1f * 0.04f + 0.06f * 0.04f);
  EXPECT_NEAR(float(m.points.size()), area / (0.002f * 0.002f), 0.2f * area / (0.002f * 0.002f));
}

TEST(IsValidMesh, SaysWhatIsWrong) {
  Mesh m;
  std::string error;
  EXPECT_FALSE(IsValidMesh(m, &error));
  EXPECT_EQ(error, "the mesh has no faces");
  m.vertices = {{0, 0, 0}, {1, 0, 0}};
  m.triangles = {{0, 1, 2}};
  EXPECT_FALSE(IsValidMesh(m, &error));
  EXPECT_EQ(error, "face 1 names vertex 3 of 2");
  m.vertices.push_back({2, 0, 0});  // on one line
  EXPECT_FALSE(IsValidMesh(m, &error));
  EXPECT_EQ(error, "every face of the mesh has zero area");
}

TEST(RenderSurface, SeesTheNearFaceOfABoxOnTheCamerasPixels) {
  // A 10 x 6 x 4 cm box's whole surface, seen from 0.5 m straight down its z axis.
  Shape box;
  box.parts.push_back(Shape::Part::Box({0, 0, 0}, {0.05f, 0.03f, 0.02f}));
  MeshViewOptions o;
  const MeshModel m = RenderMeshModel(ShapeMesh(box), o);
  Eigen::Matrix4f camera = Eigen::Matrix4f::Identity();  // at (0, 0, -0.5), looking along +z
  camera(2, 3) = -0.5f;
  const CameraIntrinsics k;
  const SurfaceView view = RenderSurface(m.points, m.normals, k, camera, 0.003f);
  ASSERT_EQ(view.points.size(), view.source.size());
  // The face at z = -0.02 is 0.48 m away: 0.1 x 0.06 m covers this many pixels, and the discs
  // on its rim reach out by up to their radius.
  const auto pixels = [&](double grow) {
    return ((0.1 + 2 * grow) * k.fx / 0.48) * ((0.06 + 2 * grow) * k.fy / 0.48);
  };
  EXPECT_GT(double(view.points.size()), 0.98 * pixels(0));
  EXPECT_LT(double(view.points.size()), pixels(0.003));
  for (std::size_t i = 0; i < view.points.size(); ++i) {
    const PointT& p = view.points[i];
    if (std::abs(p.x) > 0.047f || std::abs(p.y) > 0.027f) continue;  // the rim
    EXPECT_NEAR(m.points[std::size_t(view.source[i])].z, -0.02f, 1e-3f) << i;
    ASSERT_NEAR(p.z, 0.48f, 1e-4f) << "pixel point " << i << " is off the near face";
  }
  // With noise, depths spread by about the deviation asked for (1.5 mm at 1 m: 0.35 mm here).
  const SurfaceView noisy = RenderSurface(m.points, m.normals, k, camera, 0.003f, 0.0015f, 7);
  double sq = 0;
  for (const PointT& p : noisy.points) sq += (p.z - 0.48) * (p.z - 0.48);
  EXPECT_NEAR(std::sqrt(sq / double(noisy.points.size())), 0.0015 * 0.48 * 0.48, 0.00005);
}

TEST(MeshModel, IsVerifiedAgainstWhatItsPoseTurnsToTheCamera) {
  // The synthetic Kinect's target as its mesh gives it, at its true pose in the demo scene
  // (nudged 1 cm), and 10 cm beside it on the table.
  const CrossCaptureCase demo = MakeDemoCase(/*seed=*/5);
  const MeshModel rendered = RenderMeshModel(ShapeMesh(TargetShape()), MeshViewOptions{});
  std::string error;
  const auto model = DescribeModel(rendered.points, RecognitionOptions{}, &error);
  ASSERT_TRUE(model) << error;
  ASSERT_TRUE(model->verification().whole_surface);
  const auto at = [&](const Eigen::Vector3f& t) {
    Detection d;
    d.model_to_scene = (Eigen::Translation3f(t) * demo.truth).matrix();
    d.votes = 10;
    return d;
  };
  const CameraIntrinsics k;
  const auto verify = [&](const VerificationModel& v, const Detection& d) {
    return VerifyInstances(v, model->centroid(), demo.scene.cloud, k, {d},
                           RecognitionOptions{}.verify);
  };
  const auto kept = verify(model->verification(), at({0.01f, 0, 0}));
  ASSERT_EQ(kept.size(), 1u);
  const PoseError e = ComparePoses(kept[0].model_to_scene, demo.truth.matrix(), model->centroid());
  EXPECT_LT(e.translation_m, 0.005);
  EXPECT_LT(e.rotation_deg, 5.0);
  EXPECT_GT(kept[0].coverage, 0.4f);  // of the points facing the camera, not of the whole
  EXPECT_TRUE(verify(model->verification(), at({0.1f, 0, 0})).empty());
  // Counted as one view, the whole surface explains too little of itself to be kept.
  VerificationModel as_one_view = model->verification();
  as_one_view.whole_surface = false;
  EXPECT_TRUE(verify(as_one_view, at({0.01f, 0, 0})).empty());
}

TEST(MeshModel, IsFoundFromAnySide) {
  // The synthetic target turned every way (seeded), floating over the demo's table beside a box
  // and a ball, searched in the whole frame: a model from its mesh finds it from every side,
  // where a model captured from one side finds only that side.
  const MeshModel rendered = RenderMeshModel(ShapeMesh(TargetShape()), MeshViewOptions{});
  std::string error;
  const auto mesh = DescribeModel(rendered.points, RecognitionOptions{}, &error);
  ASSERT_TRUE(mesh) << error;
  ASSERT_TRUE(mesh->verification().whole_surface);
  const auto captured = DescribeModel(MakeDemoCase(1).model, RecognitionOptions{}, &error);
  ASSERT_TRUE(captured) << error;
  constexpr int kCases = 8;
  int found_mesh = 0, found_captured = 0, false_mesh = 0;
  for (int c = 0; c < kCases; ++c) {
    std::mt19937 random(std::uint32_t(3000 + c));
    std::normal_distribution<float> normal(0, 1);
    std::uniform_real_distribution<float> uniform(0, 1);
    Eigen::Quaternionf turn(normal(random), normal(random), normal(random), normal(random));
    turn.normalize();
    SceneObject target{TargetShape(), Eigen::Isometry3f::Identity(), kTargetLabel};
    target.pose = Eigen::Translation3f(-0.15f + 0.3f * uniform(random), 0.12f,
                                       0.8f + 0.3f * uniform(random)) *
                  turn;
    const SceneObject box{Shape{{Shape::Part::Box({0, 0, 0}, {0.08f, 0.06f, 0.08f})}},
                          PoseOnTable(-0.3f, 1.2f, 0.3f, 0.3f, 0.06f), 2};
    const SceneObject ball{Shape{{Shape::Part::Sphere({0, 0, 0}, 0.06f)}},
                           PoseOnTable(0.3f, 1.25f, 0.0f, 0.3f, 0.06f), 3};
    const RenderedFrame frame =
        RenderScene({target, box, ball}, 0.3f, CameraIntrinsics{}, KinectNoise{}, 7 + c);
    SceneQuery query;
    query.foveated = false;
    const auto found = [&](const ModelDescription& model, int* falses) {
      bool ok = false;
      for (const Detection& d :
           Recognize(model, frame.cloud, query, RecognitionOptions{}).instances) {
        const PoseError e = ComparePoses(d.model_to_scene, target.pose.matrix(), model.centroid());
        if (e.translation_m < 0.01 && e.rotation_deg < 5)
          ok = true;
        else if (falses && e.translation_m > 0.05)
          ++*falses;
      }
      return ok;
    };
    found_mesh += found(*mesh, &false_mesh);
    found_captured += found(*captured, nullptr);
  }
  std::printf("found from any side: mesh %d/%d (%d false), captured %d/%d\n", found_mesh, kCases,
              false_mesh, found_captured, kCases);
  EXPECT_GE(found_mesh, 4);  // 4 today (a fifth at 0.8 cm and 5.2 degrees)
  EXPECT_LE(false_mesh, 2);  // 0 today
  EXPECT_GE(found_mesh, found_captured + 3);
}

// A whole-surface model knows the turns that leave it the same: a cube's 24, a box's 4 (its
// half turns about each axis), none but the identity for the synthetic target; each found turn
// maps the surface onto itself.
TEST(MeshModel, KnowsTheTurnsThatLeaveItTheSame) {
  const auto turns_of = [](const Shape& shape) {
    const MeshModel rendered = RenderMeshModel(ShapeMesh(shape), MeshViewOptions{});
    std::string error;
    const auto model = DescribeModel(rendered.points, RecognitionOptions{}, &error);
    EXPECT_TRUE(model) << error;
    return model ? model->symmetries() : std::vector<Eigen::Matrix3f>{};
  };
  const std::vector<Eigen::Matrix3f> cube =
      turns_of(Shape{{Shape::Part::Box({0, 0, 0}, {0.0425f, 0.0425f, 0.0425f})}});
  ASSERT_EQ(cube.size(), 24u);
  EXPECT_TRUE(cube[0].isIdentity());
  for (const Eigen::Matrix3f& t : cube) {  // each onto the axes, within 3 degrees
    EXPECT_NEAR(t.determinant(), 1.0f, 1e-3f);
    for (int r = 0; r < 3; ++r) EXPECT_GT(t.row(r).cwiseAbs().maxCoeff(), 0.9986f) << t;
  }
  EXPECT_EQ(turns_of(Shape{{Shape::Part::Box({0, 0, 0}, {0.05f, 0.03f, 0.02f})}}).size(), 4u);
  EXPECT_EQ(turns_of(TargetShape()).size(), 1u);
}

// A cube turned every way over the demo's table: its mesh's model finds it, scored as a cube (any
// of its 24 turns is right): each match comes from whichever turn of the cube its descriptor
// found nearest, and grouping counts them as one pose (Grouping.ASymmetricModels...).
// Verification that counted the faces a sensor sees edge-on found 3. Seen face-on (case 0), a
// cube is a square: refused as flat.
TEST(MeshModel, ACubeIsFoundFromItsMesh) {
  const Shape cube{{Shape::Part::Box({0, 0, 0}, {0.0425f, 0.0425f, 0.0425f})}};
  const MeshModel rendered = RenderMeshModel(ShapeMesh(cube), MeshViewOptions{});
  std::string error;
  const auto model = DescribeModel(rendered.points, RecognitionOptions{}, &error);
  ASSERT_TRUE(model) << error;
  ASSERT_EQ(model->symmetries().size(), 24u);
  constexpr int kCases = 6;
  int found = 0, falses = 0;
  for (int c = 0; c < kCases; ++c) {
    std::mt19937 random(std::uint32_t(4000 + c));
    std::normal_distribution<float> normal(0, 1);
    std::uniform_real_distribution<float> uniform(0, 1);
    Eigen::Quaternionf turn(normal(random), normal(random), normal(random), normal(random));
    turn.normalize();
    SceneObject target{cube, Eigen::Isometry3f::Identity(), kTargetLabel};
    target.pose = Eigen::Translation3f(-0.15f + 0.3f * uniform(random), 0.12f,
                                       0.7f + 0.2f * uniform(random)) *
                  turn;
    const SceneObject ball{Shape{{Shape::Part::Sphere({0, 0, 0}, 0.06f)}},
                           PoseOnTable(0.3f, 1.25f, 0.0f, 0.3f, 0.06f), 3};
    const RenderedFrame frame =
        RenderScene({target, ball}, 0.3f, CameraIntrinsics{}, KinectNoise{}, 17 + c);
    SceneQuery query;
    query.fovea_m = target.pose.translation();
    bool ok = false;
    const RecognitionResult r = Recognize(*model, frame.cloud, query, RecognitionOptions{});
    for (const Detection& d : r.instances) {
      float least = 180;
      for (const Eigen::Matrix3f& t : model->symmetries()) {
        Eigen::Matrix4f turned = Eigen::Matrix4f::Identity();
        turned.topLeftCorner<3, 3>() = t;
        least = std::min(least, float(ComparePoses(d.model_to_scene, target.pose.matrix() * turned,
                                                   model->centroid())
                                          .rotation_deg));
      }
      const float off = (d.centroid_m - target.pose.translation()).norm();
      if (off < 0.01f && least < 5)
        ok = true;
      else if (off > 0.05f)
        ++falses;
    }
    found += ok;
  }
  std::printf("a cube from its mesh: %d/%d found, %d false\n", found, kCases, falses);
  EXPECT_GE(found, kCases - 1);
  EXPECT_EQ(falses, 0);
}

}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

// Two captures of the synthetic target, from the front and from the back, in its own frame
// (as `saccade model --captures` aligns them): described together, one index finds either side;
// the front alone finds only the front.
TEST(ViewsModel, CapturesOfTwoSidesFindEitherSide) {
  Scenario capture = *ScenarioPreset("static");
  capture.target_motion.start_xz_m = {0.0f, 0.9f};
  capture.target_motion.yaw_rad = 0.35f;
  const Cloud front = CaptureTargetModel(capture, 1);
  capture.target_motion.yaw_rad = 0.35f + float(M_PI);
  const Cloud back = CaptureTargetModel(capture, 2);
  std::string error;
  const auto one = DescribeModel(front, RecognitionOptions{}, &error);
  ASSERT_TRUE(one) << error;
  const auto back_alone = DescribeModel(back, RecognitionOptions{}, &error);
  ASSERT_TRUE(back_alone) << error;
  const auto both = DescribeModel(std::vector<Cloud>{front, back}, RecognitionOptions{}, &error);
  ASSERT_TRUE(both) << error;
  EXPECT_TRUE(both->verification().whole_surface);
  EXPECT_FALSE(one->verification().whole_surface);
  const auto finite = [](const Cloud& c) {
    return std::count_if(c.begin(), c.end(), [](const PointT& p) { return FinitePoint(p); });
  };
  EXPECT_EQ(long(both->cloud().size()), finite(front) + finite(back));
  // Each view keeps its own keypoints: at least as many descriptors as the two apart would give
  // (radii fitted to the bigger whole can only space them as the parts do or closer).
  EXPECT_GE(
      both->descriptors().size(),
      std::size_t(0.8 * double(one->descriptors().size() + back_alone->descriptors().size())));

  const auto found = [](const ModelDescription& model, float yaw, std::uint32_t seed) {
    Scenario scene = *ScenarioPreset("static");
    scene.seed = seed;
    scene.target_motion.start_xz_m = {0.05f, 0.95f};
    scene.target_motion.yaw_rad = yaw;
    const ScenarioFrame frame = RenderScenarioFrame(scene, 0, CameraIntrinsics{});
    SceneQuery query;
    query.foveated = false;
    const RecognitionResult r = Recognize(model, frame.rendered.cloud, query, RecognitionOptions{});
    const Eigen::Matrix4f truth = frame.truth.target_pose.matrix();
    for (const Detection& d : r.instances) {
      const PoseError e = ComparePoses(d.model_to_scene, truth, model.centroid());
      if (e.translation_m < 0.02 && e.rotation_deg < 10) return true;
    }
    return false;
  };
  EXPECT_TRUE(found(*both, 0.45f, 11));
  EXPECT_TRUE(found(*both, 0.45f + float(M_PI), 12));
  EXPECT_TRUE(found(*one, 0.45f, 11));
  EXPECT_FALSE(found(*one, 0.45f + float(M_PI), 12));
}

// Three captures of the target, two of its front: a model whose alignment put the second front
// capture 4 cm nearer the camera than the first. Verified as one surface, a right pose of the
// front has half its camera-facing points standing in front of the scene, and fails; the view
// most of its votes came from, verified alone, shows it right (VerifyByViews).
TEST(ViewsModel, AViewItsAlignmentMisplacedDoesNotHideTheObject) {
  Scenario capture = *ScenarioPreset("static");
  capture.target_motion.start_xz_m = {0.0f, 0.9f};
  capture.target_motion.yaw_rad = 0.35f;
  const Cloud front = CaptureTargetModel(capture, 1);
  capture.target_motion.yaw_rad = 0.65f;
  Cloud misplaced = CaptureTargetModel(capture, 3);
  capture.target_motion.yaw_rad = 0.35f + float(M_PI);
  const Cloud back = CaptureTargetModel(capture, 2);
  const Eigen::Vector3f centre = *FiniteCentroid(front);
  const Eigen::Vector3f towards_camera =
      (front.sensor_origin_.head<3>() - centre).normalized() * 0.04f;
  for (PointT& p : misplaced.points) p.getVector3fMap() += towards_camera;
  misplaced.sensor_origin_.head<3>() += towards_camera;

  Scenario scene = *ScenarioPreset("static");
  scene.seed = 11;
  scene.target_motion.start_xz_m = {0.05f, 0.95f};
  scene.target_motion.yaw_rad = 0.45f;
  const ScenarioFrame frame = RenderScenarioFrame(scene, 0, CameraIntrinsics{});
  const auto found = [&](const std::vector<Cloud>& views) {
    std::string error;
    const auto model = DescribeModel(views, RecognitionOptions{}, &error);
    EXPECT_TRUE(model) << error;
    if (!model) return false;
    SceneQuery query;
    query.foveated = false;
    const RecognitionResult r =
        Recognize(*model, frame.rendered.cloud, query, RecognitionOptions{});
    const Eigen::Matrix4f truth = frame.truth.target_pose.matrix();
    for (const Detection& d : r.instances) {
      const PoseError e = ComparePoses(d.model_to_scene, truth, model->centroid());
      if (e.translation_m < 0.02 && e.rotation_deg < 10) return true;
    }
    return false;
  };
  EXPECT_TRUE(found({front, back}));
  EXPECT_TRUE(found({front, misplaced, back}));
}

}  // namespace
}  // namespace saccade
