// A library (core/library.h): several models searched in one pass over a frame. On the
// synthetic Kinect, two objects on a table, each modelled from another capture: each is found
// at its true pose and named by its own model; a library of one model finds what Recognize
// finds; models of one size share one description of the frame.
#include "core/library.h"

#include "core/recognition.h"
#include "core/sim/synthetic.h"

#include <gtest/gtest.h>

#include <vector>

namespace saccade {
namespace {

// A second object, unlike the target: a post with a ball on top and a block at its foot.
Shape PostShape() {
  using Part = Shape::Part;
  Shape s;
  s.parts.push_back(Part::Box({0.0f, -0.01f, 0.0f}, {0.025f, 0.06f, 0.025f}));
  s.parts.push_back(Part::Sphere({0.0f, -0.08f, 0.0f}, 0.035f));
  s.parts.push_back(Part::Box({0.045f, 0.03f, 0.01f}, {0.025f, 0.02f, 0.035f}));
  return s;
}

constexpr float kTable = 0.3f;
constexpr std::uint32_t kTarget = 1, kPost = 2;

// A model of `shape` cut from a capture of it alone, standing at `pose`.
Cloud Capture(const Shape& shape, const Eigen::Isometry3f& pose, std::uint32_t label,
              std::uint32_t seed) {
  const RenderedFrame frame =
      RenderScene({{shape, pose, label}}, kTable, CameraIntrinsics{}, KinectNoise{}, seed);
  return CutModel(frame, label, pose);
}

struct Fixture {
  Eigen::Isometry3f target_pose = PoseOnTable(-0.12f, 0.95f, 0.4f, kTable);
  Eigen::Isometry3f post_pose = PoseOnTable(0.14f, 1.0f, -0.3f, kTable);
  ModelDescription target, post;
  RenderedFrame scene;

  static ModelDescription Describe(const Cloud& cloud, float ratio) {
    std::string error;
    auto d = DescribeModel(std::vector<Cloud>{cloud}, RecognitionOptions{}, &error, ratio);
    EXPECT_TRUE(d) << error;
    return std::move(*d);
  }
  explicit Fixture(float ratio = RecognitionOptions{}.library_radius_ratio)
      : target(Describe(Capture(TargetShape(), PoseOnTable(0.0f, 0.9f, 0.25f, kTable), kTarget, 1),
                        ratio)),
        post(Describe(Capture(PostShape(), PoseOnTable(0.0f, 0.9f, -0.1f, kTable), kPost, 2),
                      ratio)),
        scene(RenderScene({{TargetShape(), target_pose, kTarget}, {PostShape(), post_pose, kPost}},
                          kTable, CameraIntrinsics{}, KinectNoise{}, 3)) {}
};

SceneQuery WholeFrame() {
  SceneQuery q;
  q.foveated = false;
  return q;
}

TEST(Library, FindsEachObjectAtItsPoseAndNamesItsModel) {
  const Fixture f;
  const Library library({&f.target, &f.post}, RecognitionOptions{});
  std::string error;
  const LibraryResult r = RecognizeLibrary(library, f.scene.cloud, WholeFrame(),
                                           RecognitionOptions{}, {}, SerialFor, &error);
  ASSERT_TRUE(error.empty()) << error;
  ASSERT_EQ(r.per_model.size(), 2u);
  const Eigen::Matrix4f truth[] = {f.target_pose.matrix(), f.post_pose.matrix()};
  bool found[2] = {false, false};
  for (const Detection& d : r.instances) {
    ASSERT_TRUE(d.model == 0 || d.model == 1);
    const ModelDescription& m = library.model(std::size_t(d.model));
    const PoseError e = ComparePoses(d.model_to_scene, truth[d.model], m.centroid());
    // Wherever an instance is, it is its own model's object: never the other one.
    const PoseError other = ComparePoses(d.model_to_scene, truth[1 - d.model], m.centroid());
    EXPECT_GT(other.translation_m, 0.08) << "model " << d.model << " on the other object";
    if (e.translation_m < 0.01 && e.rotation_deg < 5) found[d.model] = true;
  }
  EXPECT_TRUE(found[0]) << "the target";
  EXPECT_TRUE(found[1]) << "the post";
}

TEST(Library, OfOneModelFindsWhatRecognizeFinds) {
  // With the options the search is given: the defaults, and a re-check's small keypoint budget.
  const Fixture f;
  const Library library({&f.post}, RecognitionOptions{});
  RecognitionOptions budget;
  budget.max_scene_keypoints = 150;
  for (const RecognitionOptions& options : {RecognitionOptions{}, budget}) {
    const LibraryResult r = RecognizeLibrary(library, f.scene.cloud, WholeFrame(), options, {});
    const RecognitionResult alone = Recognize(f.post, f.scene.cloud, WholeFrame(), options);
    ASSERT_EQ(r.per_model[0].stats.TotalKeypoints(), alone.stats.TotalKeypoints());
    EXPECT_EQ(r.per_model[0].stats.budgeted_out, alone.stats.budgeted_out);
    ASSERT_EQ(r.instances.size(), alone.instances.size());
    for (std::size_t i = 0; i < alone.instances.size(); ++i) {
      EXPECT_TRUE(r.instances[i].model_to_scene.isApprox(alone.instances[i].model_to_scene))
          << "instance " << i;
      EXPECT_EQ(r.instances[i].votes, alone.instances[i].votes);
    }
    EXPECT_EQ(r.scene_descriptions, 1u);
  }
  EXPECT_FALSE(
      Recognize(f.post, f.scene.cloud, WholeFrame(), RecognitionOptions{}).instances.empty());
}

TEST(Library, ModelsOfOneSizeShareOneDescriptionOfTheFrame) {
  // Fitted apart, the two models' SHOT radii differ; on the library's grid they are one.
  const Fixture fitted(1.0f);
  EXPECT_NE(RadiiForModel(RecognitionOptions{}, fitted.target.scale()).scene_shot_radius_m,
            RadiiForModel(RecognitionOptions{}, fitted.post.scale()).scene_shot_radius_m);
  EXPECT_EQ(Library({&fitted.target, &fitted.post}, RecognitionOptions{}).Groups(), 2u);
  const Fixture grid;
  EXPECT_EQ(Library({&grid.target, &grid.post}, RecognitionOptions{}).Groups(), 1u);
  // A model left out is not searched, and costs no description when its group is all left out.
  const LibraryResult only_post =
      RecognizeLibrary(Library({&fitted.target, &fitted.post}, RecognitionOptions{}),
                       grid.scene.cloud, WholeFrame(), RecognitionOptions{}, {false, true});
  EXPECT_EQ(only_post.scene_descriptions, 1u);
  for (const Detection& d : only_post.instances) EXPECT_EQ(d.model, 1);
}

TEST(OnRadiusGrid, RoundsTheFittedShotRadiusToItsGrid) {
  ModelScale scale;
  scale.size_m = 0.24f;  // fitted SHOT radius: 4 cm
  scale.spacing_m = 0.002f;
  EXPECT_FLOAT_EQ(OnRadiusGrid(scale, 1.0f).shot_radius_m, 0.0f);  // off: as fitted
  // 3 cm x 1.25^k: 3.75 cm is the nearest to 4 cm.
  EXPECT_NEAR(OnRadiusGrid(scale, 1.25f).shot_radius_m, 0.0375f, 1e-6f);
  EXPECT_NEAR(FitRadii(RecognitionOptions{}, OnRadiusGrid(scale, 1.25f)).scene_shot_radius_m,
              0.0375f, 1e-6f);
  EXPECT_NEAR(FitRadii(RecognitionOptions{}, scale).scene_shot_radius_m, 0.04f, 1e-6f);
}

// A plain mug's model on the printed mug scores as high as the printed mug's own (0.98 and 0.97,
// as on the library benchmark); the colours tell them apart, and the printed mug's instance stays.
TEST(ArbitrationScore, ColourAgreementTellsLookAlikesApart) {
  Detection plain, printed;
  plain.confidence = 0.98f;
  plain.colour_agreement = 0.6f;
  printed.confidence = 0.97f;
  printed.colour_agreement = 0.9f;
  EXPECT_GT(ArbitrationScore(printed), ArbitrationScore(plain));
  // Without colour measured (-1), an instance competes on its confidence alone.
  plain.colour_agreement = printed.colour_agreement = -1;
  EXPECT_GT(ArbitrationScore(plain), ArbitrationScore(printed));
  EXPECT_FLOAT_EQ(ArbitrationScore(plain), 0.98f);
}

TEST(ClaimSamePlace, WithinHalfTheSmallerModel) {
  Detection a, b;
  a.centroid_m = {0, 0, 1};
  b.centroid_m = {0.04f, 0, 1};
  EXPECT_TRUE(ClaimSamePlace(a, 0.3f, b, 0.1f));    // 4 cm < 5 cm
  EXPECT_FALSE(ClaimSamePlace(a, 0.3f, b, 0.07f));  // 4 cm > 3.5 cm
}

}  // namespace
}  // namespace saccade
