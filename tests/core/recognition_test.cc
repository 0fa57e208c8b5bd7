// Recognition on the real Kinect milk scene (../shared/data), plain and foveated, against its
// ground truth, beside PCL's stock stages; verification there. The stages' guarantees on
// hand-made inputs are in grouping_test, model_test, shot_test and neighbor_search_test.
#include "core/recognition.h"
#include "core/candidates.h"
#include "core/eval/reference_pipeline.h"
#include "io/formats/cloud_io.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace saccade {
namespace {

constexpr char kScene[] = "pcl_test/milk_cartoon_all_small_clorox.pcd";
constexpr char kMilkColor[] = "pcl_test/milk_color.pcd";
constexpr char kMilkModel[] = "pcl_data/correspondence_grouping/milk.pcd";
constexpr char kMilkPose[] = "pcl_data/correspondence_grouping/milk_pose_in_scene.txt";
const Eigen::Vector3f kCartonCentre(-0.056f, -0.127f, 0.776f);  // camera frame, metres

Cloud Load(const char* relative) {
  std::string error;
  auto cloud = LoadCloud(testing::DataPath(relative), &error);
  EXPECT_TRUE(cloud) << error;
  return cloud ? *cloud : Cloud{};
}

// The carton's true pose in the milk scene (a failure is reported).
std::optional<Eigen::Matrix4f> MilkTruth() {
  std::string error;
  auto truth = LoadPose(testing::DataPath(kMilkPose), &error);
  EXPECT_TRUE(truth) << error;
  return truth;
}

// The model of `relative`, described with the default options (a failure is reported).
std::optional<ModelDescription> Describe(const char* relative) {
  std::string error;
  auto model = DescribeModel(Load(relative), RecognitionOptions{}, &error);
  EXPECT_TRUE(model) << error;
  return model;
}

// The milk model described with the default options and its true pose in the milk scene
// (nullopt, the failure reported, when either cannot be had).
std::optional<std::pair<std::optional<ModelDescription>, std::optional<Eigen::Matrix4f>>>
DescribedMilk() {
  auto truth = MilkTruth();
  auto model = Describe(kMilkModel);
  if (!truth || !model) return std::nullopt;
  return std::make_pair(std::move(model), truth);
}

// The milk model, its true pose and the scene it is searched in (nullopt, the failure
// reported, when any cannot be had).
struct MilkInScene {
  ModelDescription model;
  Eigen::Matrix4f truth;
  Cloud scene;
};
std::optional<MilkInScene> DescribedMilkInScene() {
  auto milk = DescribedMilk();
  if (!milk) return std::nullopt;
  return MilkInScene{std::move(*milk->first), *milk->second, Load(kScene)};
}

// Exactly one instance, within 1 cm at the model centroid and 3 degrees of the truth.
void ExpectFoundAt(const RecognitionResult& r, const ModelDescription& model,
                   const Eigen::Matrix4f& truth) {
  ASSERT_EQ(r.instances.size(), 1u) << "expected the carton and nothing else";
  const PoseError e = ComparePoses(r.instances[0].model_to_scene, truth, model.centroid());
  EXPECT_LT(e.translation_m, 0.01);
  EXPECT_LT(e.rotation_deg, 3.0);
  const Eigen::Matrix3f R = r.instances[0].model_to_scene.topLeftCorner<3, 3>();
  EXPECT_NEAR(R.determinant(), 1.0f, 1e-4f);
  EXPECT_GE(r.instances[0].votes, RecognitionOptions{}.hough_threshold);
}

class MilkScene : public ::testing::TestWithParam<bool> {};  // parameter: foveated

TEST_P(MilkScene, CutOutCartonIsFoundAtTheIdentity) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkColor);
  const Cloud scene = Load(kScene);
  std::string error;
  auto model = DescribeModel(Load(kMilkColor), RecognitionOptions{}, &error);
  ASSERT_TRUE(model) << error;
  SceneQuery q;
  q.foveated = GetParam();
  q.fovea_m = kCartonCentre;
  const RecognitionResult r = Recognize(*model, scene, q, RecognitionOptions{}, SerialFor, &error);
  ASSERT_TRUE(error.empty()) << error;
  ExpectFoundAt(r, *model, Eigen::Matrix4f::Identity());
}

TEST_P(MilkScene, ModelInItsOwnFrameIsFoundAtTheTruePose) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto milk = DescribedMilk();
  ASSERT_TRUE(milk);
  const auto& [model, truth] = *milk;
  SceneQuery q;
  q.foveated = GetParam();
  q.fovea_m = kCartonCentre;
  const RecognitionResult r = Recognize(*model, Load(kScene), q, RecognitionOptions{});
  ExpectFoundAt(r, *model, *truth);
}

INSTANTIATE_TEST_SUITE_P(PlainAndFoveated, MilkScene, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Foveated" : "Plain"; });

TEST(MilkSceneFoveated, FoveaOneMetreAwayReportsNothing) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto model = Describe(kMilkModel);
  ASSERT_TRUE(model);
  SceneQuery q;
  q.fovea_m = kCartonCentre + Eigen::Vector3f(1.0f, 0.0f, 0.0f);
  const RecognitionResult r = Recognize(*model, Load(kScene), q, RecognitionOptions{});
  EXPECT_TRUE(r.instances.empty()) << r.instances.size() << " instance(s) with the fovea 1 m away";
}

TEST(MilkSceneFoveated, FoveaKeepsFarFewerPointsThanTheScene) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto model = Describe(kMilkModel);
  ASSERT_TRUE(model);
  SceneQuery q;
  q.fovea_m = kCartonCentre;
  const Cloud scene = Load(kScene);
  const RecognitionResult r = Recognize(*model, scene, q, RecognitionOptions{});
  EXPECT_LT(r.stats.TotalPoints(), CountFinite(scene) / 5);
  EXPECT_GT(r.stats.TotalKeypoints(), 50u);
  ASSERT_TRUE(r.fovea.has_value());
}

TEST(ReferencePipeline, GoldStandardFindsTheCarton) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto truth = MilkTruth();
  ASSERT_TRUE(truth);
  std::string error;
  RecognitionOptions gold;
  gold.scene_keypoint_radius_m = 0.03f;  // Table 1's r_ks keeps the test short
  const Cloud milk = Load(kMilkModel);
  auto model = DescribeReferenceModel(milk, gold, &error);
  ASSERT_TRUE(model) << error;
  const RecognitionResult r = RecognizeReference(*model, Load(kScene), gold, &error);
  ASSERT_FALSE(r.instances.empty());
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : milk.points) centroid += p.getVector3fMap();
  centroid /= static_cast<float>(milk.size());
  const PoseError e = ComparePoses(r.instances[0].model_to_scene, *truth, centroid);
  EXPECT_LT(e.translation_m, 0.01);
  EXPECT_LT(e.rotation_deg, 5.0);  // stock PCL's own pose estimate is about 3 degrees off here
}

TEST(FitRadii, MilkCartonIsFoundWithRadiiFittedToItsModel) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto truth = MilkTruth();
  ASSERT_TRUE(truth);
  std::string error;
  RecognitionOptions o;
  o.radii_from_model = true;
  const auto model = DescribeModel(Load(kMilkModel), o, &error);
  ASSERT_TRUE(model) << error;
  // Not Table 1's hand-picked 2 cm: a sixth of the carton's 32 cm diagonal.
  EXPECT_NEAR(FitRadii(o, model->scale()).scene_shot_radius_m, 0.053f, 0.002f);
  SceneQuery q;
  q.fovea_m = kCartonCentre;
  ExpectFoundAt(Recognize(*model, Load(kScene), q, o), *model, *truth);
}

// The carton's votes against the square root of the matches the model won: a bar just below
// lets it be verified, one just above leaves it unverified (few_votes) and reports nothing.
TEST(MinVoteSignificance, VerifiesOnlyVotesThatStandOutOfTheModelsMatches) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto milk = DescribedMilkInScene();
  ASSERT_TRUE(milk);
  const auto& [model, truth, scene] = *milk;
  SceneQuery q;
  q.fovea_m = kCartonCentre;
  RecognitionOptions o;
  o.min_vote_significance = 0;
  const RecognitionResult all = Recognize(model, scene, q, o);
  ExpectFoundAt(all, model, truth);
  const double z = all.instances[0].votes / std::sqrt(double(all.stats.correspondences));
  ASSERT_GT(z, 0.2) << "the carton's votes should stand out of its matches";

  o.min_vote_significance = float(z * 0.99);
  ExpectFoundAt(Recognize(model, scene, q, o), model, truth);

  o.min_vote_significance = float(z * 1.01);
  const RecognitionResult above = Recognize(model, scene, q, o);
  EXPECT_TRUE(above.instances.empty());
  ASSERT_EQ(above.verdicts.size(), above.hypotheses.size());
  std::size_t few = 0;
  for (std::size_t h = 0; h < above.hypotheses.size(); ++h) {
    const bool below =
        above.hypotheses[h].votes < z * 1.01 * std::sqrt(double(all.stats.correspondences));
    EXPECT_EQ(above.verdicts[h] == Verdict::kFewVotes, below) << "hypothesis " << h;
    few += below;
  }
  EXPECT_GE(few, 1u);
}

// By default no keypoint near the frame's table is described (a large share of a whole frame's
// are), and the carton standing on it is found as before.
TEST(TableKeypoints, AreNotDescribedAndTheCartonOnTheTableIsStillFound) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkModel);
  const auto milk = DescribedMilkInScene();
  ASSERT_TRUE(milk);
  const auto& [model, truth, scene] = *milk;
  const auto table = TablePlane(scene, CandidateOptions{});
  ASSERT_TRUE(table) << "the milk scene stands on a table";
  SceneQuery q;
  q.foveated = false;
  RecognitionOptions o = RadiiForModel(RecognitionOptions{}, model.scale());
  o.table_keypoint_distance_m = 0;
  std::string error;
  const auto all = DescribeScene(scene, q, o, SerialFor, &error);
  ASSERT_TRUE(all) << error;
  EXPECT_EQ(all->stats.table_keypoints, 0u);
  o.table_keypoint_distance_m = 0.015f;
  const auto off_table = DescribeScene(scene, q, o, SerialFor, &error);
  ASSERT_TRUE(off_table) << error;
  const std::size_t skipped = off_table->stats.table_keypoints;
  EXPECT_GT(skipped, all->descriptors.size() / 4) << "most of a tabletop frame is table";
  EXPECT_LT(off_table->descriptors.size(), all->descriptors.size() - skipped / 2);
  for (int k : off_table->descriptors.keypoint) {
    const Eigen::Vector3f p = scene[std::size_t(k)].getVector3fMap();
    ASSERT_GT(std::abs(table->head<3>().dot(p) + (*table)[3]), 0.015f) << "keypoint " << k;
  }
  ExpectFoundAt(Recognize(model, scene, q, RecognitionOptions{}), model, truth);
  // The carton cut out of the frame (NaN around it) has a largest face, and it is no table.
  Cloud cut = scene;
  for (PointT& p : cut.points)
    if ((p.getVector3fMap() - kCartonCentre).norm() > 0.12f) p.x = p.y = p.z = NAN;
  EXPECT_FALSE(TablePlane(cut, CandidateOptions{}));
}

TEST(RecognitionOptions, InvalidValuesNameTheField) {
  RecognitionOptions o;
  o.hough_bin_m = 0;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("hough_bin_m"), std::string::npos);
  o = RecognitionOptions{};
  o.scene_shot_radius_m = NAN;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("scene_shot_radius_m"), std::string::npos);
  o = RecognitionOptions{};
  o.min_vote_significance = -1;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("min_vote_significance"), std::string::npos);
  o = RecognitionOptions{};
  o.table_keypoint_distance_m = -0.01f;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("table_keypoint_distance_m"), std::string::npos);
}

TEST(VerifyInstances, KeepsTheTruePoseAndRejectsWrongOnes) {
  SACCADE_REQUIRE_DATA(kScene);
  SACCADE_REQUIRE_DATA(kMilkColor);
  const Cloud scene = Load(kScene);
  const auto model = Describe(kMilkColor);  // cut from this very scene: truth is the identity
  ASSERT_TRUE(model);
  const auto intrinsics = EstimateIntrinsics(scene);
  ASSERT_TRUE(intrinsics);
  // The truth nudged 1 cm (ICP must pull it back), and three wrong poses: the carton moved
  // onto the carpet beside itself, turned upside down in place, and lifted 10 cm towards the
  // camera (in front of what the sensor saw).
  const Eigen::Vector3f c = model->centroid();
  const auto about_centre = [&](const Eigen::Matrix3f& R, const Eigen::Vector3f& t) {
    Eigen::Affine3f a = Eigen::Translation3f(c + t) * R * Eigen::Translation3f(-c);
    Detection d;
    d.model_to_scene = a.matrix();
    d.votes = 10;
    d.centroid_m = c + t;
    return d;
  };
  const Eigen::Matrix3f I = Eigen::Matrix3f::Identity();
  const Eigen::Matrix3f flip =
      Eigen::AngleAxisf(float(EIGEN_PI), Eigen::Vector3f::UnitZ()).matrix();
  const std::vector<Detection> hypotheses = {
      about_centre(I, {0.3f, 0, 0}), about_centre(flip, {0, 0, 0}), about_centre(I, {0, 0, -0.1f}),
      about_centre(I, {0.01f, 0, 0})};
  const std::vector<Detection> kept = VerifyInstances(model->verification(), c, scene, intrinsics,
                                                      hypotheses, RecognitionOptions{}.verify);
  ASSERT_EQ(kept.size(), 1u);
  const PoseError e =
      ComparePoses(kept[0].model_to_scene, Eigen::Matrix4f::Identity(), model->centroid());
  EXPECT_LT(e.translation_m, 0.003);
  EXPECT_LT(e.rotation_deg, 2.0);
  EXPECT_GT(kept[0].fitness, 0.9f);
  EXPECT_GT(kept[0].coverage, 0.8f);
  EXPECT_GT(kept[0].colour_agreement, 0.7f);
  EXPECT_GT(kept[0].confidence, 0.5f);
  EXPECT_LE(kept[0].confidence, 1.0f);
  // With every check off and no ICP, only the exclusion of overlapping instances is left: the
  // true pose and the carton moved aside are kept, the flipped and lifted ones overlap the first.
  RecognitionOptions off;
  off.verify.min_fitness = off.verify.min_coverage = off.verify.min_depth_ratio = 0;
  off.verify.min_colour_agreement = off.verify.min_confidence = 0;
  off.verify.icp_iterations = 0;
  const std::vector<Detection> unchecked =
      VerifyInstances(model->verification(), c, scene, intrinsics, hypotheses, off.verify);
  ASSERT_EQ(unchecked.size(), 2u);
  EXPECT_NEAR((unchecked[0].centroid_m - unchecked[1].centroid_m).norm(), 0.29f, 0.02f);
}

}  // namespace
}  // namespace saccade
