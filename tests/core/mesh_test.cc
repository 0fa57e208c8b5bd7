// Models from meshes (core/mesh.h): the rendering's geometry on a box, and the synthetic Kinect's
// target found in its demo scene by a model made from its mesh alone, against the true pose.
#include "core/mesh.h"

#include "core/recognition.h"
#include "core/sim/scenario.h"
#include "core/sim/synthetic.h"
#include "core/verification.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace saccade
