// The evaluation harness as a library: the runner on the synthetic Kinect's demo case, scoring,
// protocol (b)'s seeded offsets and (c)'s attention loop, and a bad cases file. cli_test.cc
// runs `saccade eval` itself.
#include "daemon/eval/evaluation.h"
#include "daemon/eval/library_bench.h"
#include "daemon/eval/plots.h"

#include "core/sim/scenario.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace saccade::eval {
namespace {

// One scene: the demo's second capture, the model cut from its first, the truth at the
// model's centroid carried by the true pose.
struct DemoScenes {
  DemoScenes() {
    const CrossCaptureCase demo = MakeDemoCase(/*seed=*/5);
    EvalModel m;
    m.cloud = demo.model;
    m.centre = *FiniteCentroid(demo.model);
    models.push_back(m);
    Scene s;
    s.frame.cloud = std::make_shared<const Cloud>(demo.scene.cloud);
    s.truth_m = demo.truth * m.centre;
    s.truth_pose = demo.truth.matrix();
    s.name = "demo";
    scenes.push_back(s);
  }
  std::vector<EvalModel> models;
  std::vector<Scene> scenes;
};

TEST(EvalRunner, FindsTheDemoTargetFromTheFoveaOnItAndAcquiresItFromAfar) {
  const DemoScenes d;
  const Runner runner(d.models, SerialFor, /*repeat=*/1);
  EvalConfiguration c;  // Saccade's defaults, foveated
  const std::vector<Eigen::Vector3f> starts = {d.scenes[0].truth_m, Eigen::Vector3f(0, 0, 1)};
  std::vector<std::vector<Trial>> trials;
  std::vector<std::vector<Acquisition>> acquisitions;
  std::string error;
  ASSERT_TRUE(runner.Run(
      c, d.scenes, starts.size(), [&](std::size_t k, std::size_t) { return starts[k]; }, &trials,
      &acquisitions, &error))
      << error;
  ASSERT_EQ(trials.size(), 2u);
  // On the object (protocol a): found in one frame, and nothing else.
  const Totals on = Score(trials[0], d.scenes, 0.08f);
  EXPECT_EQ(on.tp, 1);
  EXPECT_EQ(on.fp, 0);
  EXPECT_TRUE(trials[0][0].evidence.found);
  EXPECT_GT(trials[0][0].evidence.correct_correspondences, 0);  // the truth pose explains some
  EXPECT_EQ(acquisitions[0][0].frames, 1);
  // From (0, 0, 1) m the attention loop gets there in a few frames (protocol c).
  EXPECT_GT(acquisitions[1][0].frames, 0);
  EXPECT_LE(acquisitions[1][0].frames, 30);
}

TEST(EvalProtocols, OffObjectOffsetsAre15cmAndSeededByTheCase) {
  for (std::size_t i = 0; i < 50; ++i) {
    EXPECT_NEAR(OffObject(i).norm(), 0.15f, 1e-5f);
    EXPECT_TRUE(OffObject(i).isApprox(OffObject(i)));
  }
  EXPECT_FALSE(OffObject(0).isApprox(OffObject(1), 1e-3f));
  EXPECT_EQ(SweepOffsets().size(), 8u);
  EXPECT_FLOAT_EQ(SweepOffsets().back().x(), 0.35f);
}

TEST(EvalCases, AMissingCasesFileIsOneErrorNamingIt) {
  std::vector<EvalModel> models;
  std::vector<Scene> scenes;
  std::string error;
  EXPECT_FALSE(
      LoadCaseScenes("/nonexistent/cases.yaml", "/nonexistent", {}, 1, &models, &scenes, &error));
  EXPECT_NE(error.find("/nonexistent/cases.yaml"), std::string::npos) << error;
  EXPECT_TRUE(scenes.empty());
}

// The plots' script: every plot titled, its axes labelled with units, its legend below the
// axes, and never more than kMaxSeries series; 18 configurations make three pages, the best
// (most true positives at 8 cm, then fewest false) on the first.
// The library benchmark on six cases of the cross-capture benchmark (../shared/data/mosd_xcap):
// the coffee can in test36 and test38, the cocoa carton and the beige bowl in test62 and test63,
// each identity a model of its other captures in the file. A cases file of those six and an
// identities.csv of those four captures' labelled objects are written beside each other.
TEST(EvalLibrary, ThreeIdentitiesAreSearchedInFourCapturesAndScoredAgainstTheirLabels) {
  SACCADE_REQUIRE_DATA("mosd_xcap/cases_with_pose.yaml");
  const std::set<std::string> wanted = {
      "coffee_can-test36-in-test38",   "coffee_can-test38-in-test36",
      "cocoa_carton-test62-in-test63", "cocoa_carton-test63-in-test62",
      "beige_bowl-test63-in-test62",   "beige_bowl-test62-in-test63"};
  const std::string dir = ::testing::TempDir() + "library_bench/";
  std::filesystem::create_directories(dir);
  {
    std::ifstream in(saccade::testing::DataPath("mosd_xcap/cases_with_pose.yaml"));
    std::ofstream out(dir + "cases.yaml");
    out << "cases:\n";
    bool keep = false;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("  - name: ", 0) == 0) keep = wanted.count(line.substr(10)) > 0;
      if (keep) out << line << "\n";
    }
  }
  {
    std::ifstream in(saccade::testing::DataPath("mosd_xcap/identities.csv"));
    std::ofstream out(dir + "identities.csv");
    std::string line;
    std::getline(in, line);
    out << line << "\n";
    for (; std::getline(in, line);)
      for (const char* scene :
           {"test/test36.pcd,", "test/test38.pcd,", "test/test62.pcd,", "test/test63.pcd,"})
        if (line.rfind(scene, 0) == 0)
          out << saccade::testing::DataPath("mosd_xcap/") << line << "\n";
  }
  LibraryBenchOptions options;
  options.sizes = {1, 0};
  std::vector<LibraryRow> rows;
  std::string error;
  ASSERT_TRUE(
      RunLibraryBench(dir + "cases.yaml", saccade::testing::DataPath(""), options, &rows, &error))
      << error;
  ASSERT_EQ(rows.size(), 8u);  // four captures, two sizes
  std::map<int, int> instances, found, false_instances;
  for (const LibraryRow& r : rows) {
    instances[r.size] += r.instances;
    found[r.size] += r.found;
    false_instances[r.size] += r.false_instances;
    const bool can =
        r.scene.find("test36") != std::string::npos || r.scene.find("test38") != std::string::npos;
    if (can) {
      EXPECT_EQ(r.detail.rfind("coffee_can:true:0.99", 0), 0u) << r.scene << ": " << r.detail;
    }
    // Three models on two radii of the grid (recognition.library_radius_ratio): two descriptions.
    EXPECT_EQ(r.descriptions, r.size == 1 ? 1 : 2) << r.scene << " " << r.size;
    // The costliest model alone is timed for a library of several only.
    EXPECT_EQ(r.costliest_alone_ms > 0, r.size > 1) << r.scene << " " << r.size;
    for (const LibraryInstance& c : r.candidates)
      EXPECT_TRUE(c.identity == "coffee_can" || c.identity == "cocoa_carton" ||
                  c.identity == "beige_bowl")
          << c.identity;
  }
  // A library of one looks for one object the capture shows; of all three, for each of the
  // capture's sure objects of the three identities: the can in test36 and test38, the carton and
  // the bowl in test62 and test63. Today: the can in both (0.99), the bowl in both (0.89 and
  // 0.56: with the table's keypoints left out, recognition.table_keypoint_distance_m, its votes
  // stand out of the fewer matches it wins); with all three, the carton in test63 too, the
  // carton in test62 missed. False: a second can beside the can in test36 (0.65), and with
  // three models also one in test38, two in test63 and a carton on another place of test62.
  EXPECT_EQ(instances[1], 4);
  EXPECT_EQ(instances[3], 6);
  EXPECT_EQ(found[1], 4);
  EXPECT_EQ(found[3], 5);
  EXPECT_EQ(false_instances[1], 1);
  EXPECT_EQ(false_instances[3], 5);
}

TEST(EvalPlots, EighteenConfigurationsMakePagesOfAtMostEightTheBestFirst) {
  std::vector<PlotSeries> configs;
  for (int i = 0; i < 18; ++i) configs.push_back({"c" + std::to_string(i), 0, i});
  configs[17].tp = 12, configs[17].fp = 0;  // the best, last in the file
  configs[5].tp = 12, configs[5].fp = 1;
  configs[9].tp = 3;
  const PlotScript script = MakePlotScript(configs, {"c17", "c5"}, 12);
  EXPECT_EQ(script.pngs, (std::vector<std::string>{"thresholds_tp.png", "thresholds_tp-2.png",
                                                   "thresholds_tp-3.png", "thresholds_fp.png",
                                                   "thresholds_fp-2.png", "thresholds_fp-3.png",
                                                   "sweep.png", "sweep_attention.png"}));
  EXPECT_NE(script.text.find("set key below"), std::string::npos);
  EXPECT_NE(script.text.find("set xlabel 'distance threshold (cm)'"), std::string::npos);
  EXPECT_NE(script.text.find("set xlabel 'fovea distance from the object, along x (cm)'"),
            std::string::npos);
  // Each plot: its output, a title and a y label set before it, and at most 8 series.
  std::istringstream lines(script.text);
  std::vector<std::vector<std::string>> plots;  // the series titles of each plot
  bool titled = false, labelled = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("set title \"", 0) == 0) titled = line.size() > 20;
    if (line.rfind("set ylabel \"", 0) == 0) labelled = line.find('(') != std::string::npos;
    if (line.rfind("plot ", 0) == 0) {
      EXPECT_TRUE(titled && labelled) << line;
      titled = labelled = false;
      plots.emplace_back();
    }
    if (line.rfind("plot ", 0) == 0 || line.rfind("     '", 0) == 0) {
      const auto at = line.find(" title \"");
      ASSERT_NE(at, std::string::npos) << line;
      plots.back().push_back(line.substr(at + 8, line.find('"', at + 8) - at - 8));
    }
  }
  ASSERT_EQ(plots.size(), script.pngs.size());
  for (const auto& series : plots) EXPECT_LE(series.size(), kMaxSeries);
  EXPECT_EQ(plots[0], (std::vector<std::string>{"c17", "c5", "c9", "c0", "c1", "c2", "c3", "c4"}));
  EXPECT_EQ(plots[2], (std::vector<std::string>{"c15", "c16"}));
  EXPECT_EQ(plots[3], plots[0]);  // the false positives' pages hold the same configurations
  EXPECT_EQ(plots[6], (std::vector<std::string>{"c17", "c5"}));
  // A paged plot says which of them it holds and where the rest are.
  EXPECT_NE(script.text.find("configurations 9-16 of 18, ranked by true positives at 8 cm; the "
                             "rest in thresholds_tp.png thresholds_tp-3.png"),
            std::string::npos);
}

// Without a sweep there is no sweep plot (not an empty one).
TEST(EvalPlots, NoSweepNoSweepPlots) {
  const PlotScript script = MakePlotScript({{"saccade", 5, 1}}, {}, 12);
  EXPECT_EQ(script.pngs, (std::vector<std::string>{"thresholds_tp.png", "thresholds_fp.png"}));
  EXPECT_EQ(script.text.find("sweep"), std::string::npos);
}

}  // namespace
}  // namespace saccade::eval
