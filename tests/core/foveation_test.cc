// Properties of the foveated model (paper §3) over many seeded random parameter sets.
#include "core/foveation.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace saccade {
namespace {

constexpr int kTrials = 200;

struct Scenario {
  FoveaOptions options;
  Eigen::Vector3f fovea;
  Cloud cloud;
  Box bounds;
};

// A random cloud around a random fixed outer box, with a random fovea near or inside it.
Scenario RandomScenario(std::mt19937* rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Scenario s;
  FoveaOptions& o = s.options;
  o.finest_level = 1 + static_cast<int>(unit(*rng) * 5);
  o.outer_box_from_scene = false;
  o.outer_size_m =
      Eigen::Vector3f(0.5f + 3 * unit(*rng), 0.5f + 3 * unit(*rng), 0.5f + 3 * unit(*rng));
  o.outer_min_corner_m = Eigen::Vector3f(-2 * unit(*rng), -2 * unit(*rng), unit(*rng));
  for (int i = 0; i < 3; ++i) o.inner_size_m[i] = o.outer_size_m[i] * (0.05f + 0.9f * unit(*rng));
  o.growth_m =
      unit(*rng) < 0.3f ? Eigen::Vector3f::Zero() : Eigen::Vector3f::Constant(0.3f * unit(*rng));
  o.outer_density_m = 0.0f;  // keep every point: the partition is then exact
  o.inner_density_m = 0.0f;
  for (int i = 0; i < 3; ++i)
    s.fovea[i] = o.outer_min_corner_m[i] + o.outer_size_m[i] * (-0.2f + 1.4f * unit(*rng));
  for (int i = 0; i < 2000; ++i) {
    PointT p;
    for (int a = 0; a < 3; ++a)
      p.data[a] = o.outer_min_corner_m[a] + o.outer_size_m[a] * (-0.1f + 1.2f * unit(*rng));
    s.cloud.push_back(p);
  }
  s.bounds = *BoundingBox(s.cloud);
  return s;
}

TEST(FoveationEquations, DisplacementAndSizeAtFirstAndLastLevel) {
  std::mt19937 rng(7);
  for (int t = 0; t < kTrials; ++t) {
    const Scenario s = RandomScenario(&rng);
    const FoveaOptions& o = s.options;
    const FoveaGeometry g = ComputeFoveaGeometry(o, s.bounds, s.fovea);
    const Eigen::Vector3f F = g.fovea_in_box_m - 0.5f * o.outer_size_m;
    const int m = o.finest_level;
    EXPECT_TRUE(LevelDisplacement(0, m, o.outer_size_m, o.inner_size_m, F).isZero(1e-6f));
    EXPECT_TRUE((LevelDisplacement(m, m, o.outer_size_m, o.inner_size_m, F) + 0.5f * o.inner_size_m)
                    .isApprox(g.fovea_in_box_m, 1e-4f));
    EXPECT_TRUE(LevelSize(0, m, o.outer_size_m, o.inner_size_m).isApprox(o.outer_size_m, 1e-5f));
    EXPECT_TRUE(LevelSize(m, m, o.outer_size_m, o.inner_size_m).isApprox(o.inner_size_m, 1e-5f));
  }
}

TEST(FoveationGeometry, LevelsAreNestedAndClampedToTheOuterBox) {
  std::mt19937 rng(11);
  for (int t = 0; t < kTrials; ++t) {
    const Scenario s = RandomScenario(&rng);
    const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
    ASSERT_EQ(static_cast<int>(g.levels.size()), s.options.finest_level + 1);
    EXPECT_TRUE(g.levels[0].min.isZero() && g.levels[0].max.isApprox(g.outer_size_m));
    for (std::size_t k = 0; k < g.levels.size(); ++k) {
      EXPECT_TRUE(g.OuterBox().ContainsBox(g.levels[k])) << "trial " << t << " level " << k;
      if (k + 1 < g.levels.size()) {
        EXPECT_TRUE(g.levels[k].ContainsBox(g.levels[k + 1])) << "trial " << t << " level " << k;
      }
    }
  }
}

TEST(FoveationCloud, LevelsAreDisjointAndTheirUnionIsTheOuterBoxCrop) {
  std::mt19937 rng(13);
  for (int t = 0; t < kTrials; ++t) {
    const Scenario s = RandomScenario(&rng);
    const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
    const FoveatedCloud fc = Foveate(s.cloud, s.options, g);
    std::set<int> seen;
    for (std::size_t j = 0; j < fc.source_index.size(); ++j) {
      const int i = fc.source_index[j];
      EXPECT_TRUE(seen.insert(i).second) << "point " << i << " in two levels";
      // Each point sits in the level Algorithm 1 gives it: inside box k, not inside box k+1.
      EXPECT_EQ(LevelOf(g, s.cloud[i].getVector3fMap()), fc.level[j]);
    }
    for (int i = 0; i < static_cast<int>(s.cloud.size()); ++i) {
      const bool in_outer = g.OuterBox().Contains(g.box_from_camera * s.cloud[i].getVector3fMap());
      EXPECT_EQ(in_outer, seen.count(i) == 1) << "trial " << t << " point " << i;
    }
  }
}

TEST(FoveationCloud, DownsampledLevelsKeepOnlyOriginalPointsOfTheirRegion) {
  std::mt19937 rng(17);
  for (int t = 0; t < 50; ++t) {
    Scenario s = RandomScenario(&rng);
    s.options.outer_density_m = 0.2f;
    s.options.inner_density_m = 0.05f;
    const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
    const FoveatedCloud fc = Foveate(s.cloud, s.options, g);
    for (std::size_t j = 0; j < fc.source_index.size(); ++j) {
      EXPECT_EQ(LevelOf(g, fc.cloud[j].getVector3fMap()), fc.level[j]);
      EXPECT_EQ(fc.cloud[j].getVector3fMap(), s.cloud[fc.source_index[j]].getVector3fMap());
    }
    for (int k = 0; k < fc.NumLevels(); ++k)
      EXPECT_EQ(fc.LevelCloud(k).size(), fc.LevelPointCount(k));
  }
}

TEST(FoveationGrowth, ZeroGrowthPutsTheFoveaBoxAroundTheFixation) {
  std::mt19937 rng(19);
  for (int t = 0; t < kTrials; ++t) {
    Scenario s = RandomScenario(&rng);
    s.options.growth_m.setZero();
    const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
    const Eigen::Vector3f half = 0.5f * s.options.inner_size_m;
    const Box& inner = g.levels.back();
    const Eigen::Vector3f lo = (g.fovea_in_box_m - half).cwiseMax(Eigen::Vector3f::Zero());
    const Eigen::Vector3f hi = (g.fovea_in_box_m + half).cwiseMin(g.outer_size_m);
    EXPECT_TRUE(inner.min.isApprox(lo, 1e-4f) || (inner.min - lo).norm() < 1e-4f);
    EXPECT_TRUE(inner.max.isApprox(hi, 1e-4f) || (inner.max - hi).norm() < 1e-4f);
  }
}

TEST(FoveationGrowth, VeryLargeGrowthMeansNoFoveation) {
  std::mt19937 rng(23);
  for (int t = 0; t < 50; ++t) {
    Scenario s = RandomScenario(&rng);
    s.options.growth_m.setConstant(1e6f);
    const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
    const FoveatedCloud fc = Foveate(s.cloud, s.options, g);
    for (std::size_t j = 0; j < fc.level.size(); ++j)
      EXPECT_EQ(fc.level[j], s.options.finest_level);
    for (int k = 0; k < s.options.finest_level; ++k) EXPECT_EQ(fc.LevelPointCount(k), 0u);
  }
}

TEST(FoveationGrowth, TwoLevelsWork) {
  std::mt19937 rng(29);
  Scenario s = RandomScenario(&rng);
  s.options.finest_level = 1;
  const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
  const FoveatedCloud fc = Foveate(s.cloud, s.options, g);
  ASSERT_EQ(fc.NumLevels(), 2);
  // Both levels hold points, and each point sits in the level its position says (the counts
  // summing to the cloud's size would hold by construction).
  EXPECT_GT(fc.LevelPointCount(0), 0u);
  EXPECT_GT(fc.LevelPointCount(1), 0u);
  for (std::size_t j = 0; j < fc.cloud.size(); ++j)
    EXPECT_EQ(LevelOf(g, fc.cloud[j].getVector3fMap()), fc.level[j]) << "point " << j;
}

TEST(FoveationGeometry, OuterBoxFromTheSceneCoversEveryPoint) {
  std::mt19937 rng(31);
  Scenario s = RandomScenario(&rng);
  s.options.outer_box_from_scene = true;
  const FoveaGeometry g = ComputeFoveaGeometry(s.options, s.bounds, s.fovea);
  const FoveatedCloud fc = Foveate(s.cloud, s.options, g);
  EXPECT_EQ(fc.cloud.size(), s.cloud.size());
}

TEST(FoveationGeometry, OrientedOuterBoxRotatesTheLevels) {
  FoveaOptions o;
  o.outer_box_from_scene = false;
  o.outer_size_m = Eigen::Vector3f(2, 2, 2);
  o.outer_min_corner_m = Eigen::Vector3f(0, 0, 0);
  o.outer_orientation =
      Eigen::AngleAxisf(EIGEN_PI / 2, Eigen::Vector3f::UnitZ());  // box x = camera y
  o.inner_size_m = Eigen::Vector3f(0.2f, 0.2f, 0.2f);
  o.finest_level = 1;
  const Eigen::Vector3f fovea(-0.5f, 0.5f, 1.0f);  // box coordinates (0.5, 0.5, 1.0)
  const FoveaGeometry g = ComputeFoveaGeometry(o, Box{}, fovea);
  EXPECT_TRUE(g.fovea_in_box_m.isApprox(Eigen::Vector3f(0.5f, 0.5f, 1.0f), 1e-5f));
  EXPECT_EQ(LevelOf(g, fovea), 1);
  EXPECT_EQ(LevelOf(g, Eigen::Vector3f(0.5f, 0.5f, 1.0f)), -1);  // outside the rotated box
}

struct InvalidCase {
  const char* field;
  void (*mutate)(FoveaOptions*);
};

TEST(FoveaOptions, InvalidParametersAreRejectedNamingTheField) {
  const InvalidCase cases[] = {
      {"finest_level", [](FoveaOptions* o) { o->finest_level = 0; }},
      {"inner_size_m",
       [](FoveaOptions* o) {
         o->outer_box_from_scene = false;
         o->inner_size_m = Eigen::Vector3f(4, 0.1f, 0.1f);
       }},
      {"outer_size_m",
       [](FoveaOptions* o) {
         o->outer_box_from_scene = false;
         o->outer_size_m.x() = 0;
       }},
      {"inner_size_m", [](FoveaOptions* o) { o->inner_size_m.y() = -1; }},
      {"outer_keypoint_radius_m", [](FoveaOptions* o) { o->outer_keypoint_radius_m = 0; }},
      {"inner_keypoint_radius_m", [](FoveaOptions* o) { o->inner_keypoint_radius_m = NAN; }},
      {"growth_m", [](FoveaOptions* o) { o->growth_m.z() = NAN; }},
      {"outer_density_m", [](FoveaOptions* o) { o->outer_density_m = -0.1f; }},
      {"outer_min_corner_m",
       [](FoveaOptions* o) {
         o->outer_box_from_scene = false;
         o->outer_min_corner_m.x() = NAN;
       }},
  };
  for (const auto& c : cases) {
    FoveaOptions o;
    c.mutate(&o);
    std::string error;
    EXPECT_FALSE(o.IsValid(&error)) << c.field;
    EXPECT_NE(error.find(c.field), std::string::npos)
        << "'" << error << "' should name " << c.field;
  }
  std::string error;
  EXPECT_TRUE(FoveaOptions{}.IsValid(&error)) << error;
}

}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

TEST(FoveationDeathTest, InvalidOptionsAreABugThatStopsWithTheReason) {
  FoveaOptions o;
  o.finest_level = 0;  // needs at least two levels
  EXPECT_DEATH(ComputeFoveaGeometry(o, Box{}, Eigen::Vector3f(0, 0, 1)),
               "precondition failed: o.IsValid\\(\\): .*finest_level");
}

}  // namespace
}  // namespace saccade
