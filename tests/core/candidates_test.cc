// Whole-frame candidates: the target on a cluttered table ranks first, colour tells two
// like-shaped objects apart, thickness a solid from a flat board, and degenerate frames give no
// candidate.
#include "core/candidates.h"
#include "core/mesh.h"
#include "core/model.h"
#include "core/sim/scenario.h"
#include "core/sim/synthetic.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace saccade {
namespace {

ModelSignature TargetSignature(const Cloud& model) {
  return SignModel(model, MeasureModel(model).spacing_m);
}

// Depth alone cannot tell the target from clutter of its size (the scene's largest box is
// 16 x 12 x 16 cm, the target 14 x 14 x 10 cm): it is among the candidates, and every candidate
// stands on the table, none is the table.
TEST(Candidates, TheTargetAmongClutterIsACandidateAndTheTableIsNot) {
  const Cloud model = SyntheticTargetModel(7);
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    Scenario s = *ScenarioPreset("static");
    s.seed = seed;
    s.target_motion.start_xz_m = {0.12f * static_cast<float>(seed) - 0.3f, 1.0f};
    const ScenarioFrame frame = RenderScenarioFrame(s, 0, CameraIntrinsics{});
    CandidateStats stats;
    const auto candidates = ProposeCandidates(frame.rendered.cloud, CameraIntrinsics{},
                                              TargetSignature(model), CandidateOptions{}, &stats);
    EXPECT_TRUE(stats.plane_found);
    EXPECT_LT(stats.above_plane, stats.coarse_points / 3) << "the table is removed";
    ASSERT_FALSE(candidates.empty()) << "seed " << seed;
    EXPECT_LE(candidates.size(), 4u) << "the target and three pieces of clutter";
    EXPECT_TRUE(std::any_of(
        candidates.begin(), candidates.end(),
        [&](const Candidate& c) { return (c.centre_m - frame.truth.centroid_m).norm() < 0.05f; }))
        << "seed " << seed;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      EXPECT_LT(candidates[i].centre_m.y(), s.table_height_m - 0.02f) << "above the table (y down)";
      if (i > 0) {
        EXPECT_LE(candidates[i].score, candidates[i - 1].score);
      }
    }
  }
}

// Two copies of the target, one painted red and one green: a red model finds the red one first,
// a green model the green one, and without colour both are proposed.
TEST(Candidates, ColourTellsLikeShapesApart) {
  const float table = 0.25f;
  std::vector<SceneObject> objects(2);
  objects[0] = {TargetShape(), PoseOnTable(-0.2f, 1.0f, 0.3f, table), 1};
  objects[1] = {TargetShape(), PoseOnTable(0.2f, 1.0f, 0.3f, table), 2};
  RenderedFrame frame = RenderScene(objects, table, CameraIntrinsics{}, KinectNoise{}, 5);
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    PointT& p = frame.cloud[i];
    const std::uint32_t l = frame.label[i];
    p.r = l == 1 ? 200 : 120, p.g = l == 2 ? 200 : 120, p.b = 120;
  }
  Cloud red = CutModel(frame, 1, objects[0].pose);
  Cloud green = CutModel(frame, 2, objects[1].pose);
  const Eigen::Vector3f at[2] = {objects[0].pose.translation(), objects[1].pose.translation()};
  const auto first = [&](const Cloud& model, const CandidateOptions& o) {
    const auto c = ProposeCandidates(frame.cloud, CameraIntrinsics{}, TargetSignature(model), o);
    EXPECT_GE(c.size(), 2u);
    return c.empty() ? Eigen::Vector3f(0, 0, 0) : c.front().centre_m;
  };
  EXPECT_LT((first(red, {}) - at[0]).norm(), 0.1f);
  EXPECT_LT((first(green, {}) - at[1]).norm(), 0.1f);
  CandidateOptions geometry;
  geometry.colour_weight = 0;
  const auto both =
      ProposeCandidates(frame.cloud, CameraIntrinsics{}, TargetSignature(red), geometry);
  ASSERT_GE(both.size(), 2u);
  for (const Eigen::Vector3f& object : at)
    EXPECT_TRUE((both[0].centre_m - object).norm() < 0.1f ||
                (both[1].centre_m - object).norm() < 0.1f);
}

// A flat board as wide and tall as the target, standing face-on beside it, covers as many
// pixels: by amount alone the two are alike. The target is thick as its model is and ranks
// first; the board, a centimetre thick, scores a fraction of its fill.
TEST(Candidates, AFlatBoardOfTheTargetsSizeRanksBelowTheTarget) {
  const float table = 0.25f;
  Shape board;
  board.parts.push_back(Shape::Part::Box({0, 0, 0}, {0.07f, 0.06f, 0.005f}));
  std::vector<SceneObject> objects(2);
  objects[0] = {TargetShape(), PoseOnTable(-0.2f, 1.0f, 0.3f, table), 1};
  objects[1] = {board, PoseOnTable(0.2f, 1.0f, 0.0f, table, 0.06f), 2};
  const RenderedFrame frame = RenderScene(objects, table, CameraIntrinsics{}, KinectNoise{}, 5);
  const Cloud model = CutModel(frame, 1, objects[0].pose);
  const ModelSignature signature = TargetSignature(model);
  EXPECT_GT(signature.thickness_m, 0.01f);
  const Eigen::Vector3f target = objects[0].pose.translation(),
                        flat = objects[1].pose.translation();
  const auto near = [](const Candidate& c, const Eigen::Vector3f& at) {
    return (c.centre_m - at).norm() < 0.1f;
  };
  const auto candidates = ProposeCandidates(frame.cloud, CameraIntrinsics{}, signature, {});
  ASSERT_GE(candidates.size(), 2u);
  EXPECT_TRUE(near(candidates[0], target));
  EXPECT_GT(candidates[0].shape, 0.8f);
  const auto on_board = std::find_if(candidates.begin(), candidates.end(),
                                     [&](const Candidate& c) { return near(c, flat); });
  ASSERT_NE(on_board, candidates.end());
  EXPECT_LT(on_board->shape, 0.5f);
  EXPECT_GT(on_board->fill, 0.5f) << "as many pixels as the target: only its shape tells";
  CandidateOptions amount_only;
  amount_only.shape_weight = 0;
  for (const Candidate& c :
       ProposeCandidates(frame.cloud, CameraIntrinsics{}, signature, amount_only))
    EXPECT_EQ(c.shape, 1.0f) << "not looked at";
}

// A cube's whole surface (from its mesh) shows a camera one face's area face-on and about 1.7
// of them corner-on: a window of either amount is the cube's size, and it is as thick as the
// median side. Its material greys carry no
// colour to look for. A cube seen face-on in a frame fills its window, and it stands apart from
// the table it is on.
TEST(Candidates, AWholeSurfaceIsAsLargeAsAnyOfItsSides) {
  const float half = 0.0425f, face = 4 * half * half;
  const Shape cube{{Shape::Part::Box({0, 0, 0}, {half, half, half})}};
  MeshModel rendered = RenderMeshModel(ShapeMesh(cube), MeshViewOptions{});
  for (PointT& p : rendered.points) p.r = p.g = p.b = 120;
  std::string error;
  const auto model = DescribeModel(rendered.points, RecognitionOptions{}, &error);
  ASSERT_TRUE(model) << error;
  const ModelSignature signature = SignModel(*model);
  EXPECT_GT(signature.seen_area_min_m2, 0.95f * face);
  EXPECT_LT(signature.seen_area_min_m2, 1.25f * face);
  EXPECT_GT(signature.seen_area_max_m2, 1.5f * face);
  EXPECT_LT(signature.seen_area_max_m2, 1.9f * face);
  EXPECT_GT(signature.thickness_m, 0.25f * half) << "the median side shows two faces or three";
  EXPECT_LT(signature.thickness_m, 0.6f * half);
  EXPECT_FALSE(signature.coloured) << "material greys";

  const float table = 0.25f;
  const SceneObject facing{cube, PoseOnTable(0.0f, 0.8f, 0.0f, table, half), 1};
  const RenderedFrame frame = RenderScene({facing}, table, CameraIntrinsics{}, KinectNoise{}, 5);
  CandidateOptions apart;
  apart.apart_weight = 1;
  const auto candidates = ProposeCandidates(frame.cloud, CameraIntrinsics{}, signature, apart);
  ASSERT_FALSE(candidates.empty());
  EXPECT_LT((candidates[0].centre_m - facing.pose.translation()).norm(), 0.05f);
  EXPECT_GT(candidates[0].fill, 0.9f) << "one face's pixels are a side the cube has";
  EXPECT_GT(candidates[0].apart, 0.8f) << "nothing around it but the table";
}

// A mesh's sides range in area (the cube's from one face to nearly two): many places in a frame
// hold an amount within that range, a part of something larger among them. So the default
// looks at how much stands around a window by as much as the range is wide. A cube alone and
// four more in a row, touching, on one table: with the range closed (as a one-sided capture,
// apart_weight 0, not looked at) the lone cube and a piece of the row score alike; with the
// mesh's range the lone cube leads by a clear margin.
TEST(Candidates, AMeshsWideRangeOfAreasLooksAtWhatStandsAround) {
  const float half = 0.0425f;
  const Shape cube{{Shape::Part::Box({0, 0, 0}, {half, half, half})}};
  MeshModel rendered = RenderMeshModel(ShapeMesh(cube), MeshViewOptions{});
  std::string error;
  const auto model = DescribeModel(rendered.points, RecognitionOptions{}, &error);
  ASSERT_TRUE(model) << error;
  const ModelSignature signature = SignModel(*model);
  ModelSignature one_sided = signature;
  one_sided.seen_area_min_m2 = one_sided.seen_area_max_m2 = signature.seen_area_m2;

  const float table = 0.25f;
  std::vector<SceneObject> objects;
  objects.push_back({cube, PoseOnTable(-0.3f, 1.0f, 0.4f, table, half), 1});
  for (int i = 0; i < 4; ++i)
    objects.push_back(
        {cube, PoseOnTable(0.05f + 0.09f * float(i), 1.0f, 0.1f * float(i), table, half), 2});
  const RenderedFrame frame = RenderScene(objects, table, CameraIntrinsics{}, KinectNoise{}, 5);
  // The lone cube's score less the best elsewhere.
  const auto lead = [&](const std::vector<Candidate>& candidates) {
    float lone = 0, row = 0;
    for (const Candidate& c : candidates) {
      const bool alone = (c.centre_m - objects[0].pose.translation()).norm() < 0.05f;
      float& best = alone ? lone : row;
      best = std::max(best, c.score);
    }
    EXPECT_GT(lone, 0.5f) << "the lone cube is a candidate";
    return lone - row;
  };
  const auto closed = ProposeCandidates(frame.cloud, CameraIntrinsics{}, one_sided, {});
  for (const Candidate& c : closed) EXPECT_EQ(c.apart, 1.0f) << "apart_weight 0: not looked at";
  EXPECT_LT(std::abs(lead(closed)), 0.05f) << "by amount and thickness, alike";
  EXPECT_GT(lead(ProposeCandidates(frame.cloud, CameraIntrinsics{}, signature, {})), 0.1f)
      << "the row has more around each of its pieces";
}

TEST(Candidates, NothingFromAnUnorganizedOrEmptyFrame) {
  const ModelSignature model = TargetSignature(SyntheticTargetModel(7));
  Cloud flat;
  flat.push_back(PointT{});
  EXPECT_TRUE(ProposeCandidates(flat, CameraIntrinsics{}, model, {}).empty());
  Cloud holes(64, 48);
  for (PointT& p : holes) p.x = p.y = p.z = NAN;
  EXPECT_TRUE(ProposeCandidates(holes, CameraIntrinsics{}, model, {}).empty());
}

TEST(Candidates, OptionsAreValidated) {
  std::string error;
  EXPECT_TRUE(CandidateOptions{}.IsValid(&error)) << error;
  // One key out of range: refused, and the error names it.
  const auto refused = [&](void (*spoil)(CandidateOptions*), const std::string& key) {
    CandidateOptions o;
    spoil(&o);
    EXPECT_FALSE(o.IsValid(&error)) << key;
    EXPECT_NE(error.find(key), std::string::npos) << error;
  };
  refused([](CandidateOptions* o) { o->stride_px = 0; }, "stride_px");
  refused([](CandidateOptions* o) { o->colour_weight = 1.5f; }, "colour_weight");
  refused([](CandidateOptions* o) { o->shape_weight = -0.1f; }, "shape_weight");
  refused([](CandidateOptions* o) { o->apart_weight = 2; }, "apart_weight");
}

}  // namespace
}  // namespace saccade
