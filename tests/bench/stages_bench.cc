// Google Benchmark over the hot stages of a frame, on the synthetic Kinect's demo case (a
// 640x480 frame: the target among clutter, and a model cut from another capture). `make
// bench-stages` runs it; `saccade bench` times the whole pipeline on real data
// (docs/BENCHMARKS.md). A benchmark, not a test: nothing here asserts a time.
#include "core/candidates.h"
#include "core/foveation.h"
#include "core/recognition.h"
#include "core/registration.h"
#include "core/sim/scenario.h"
#include "core/tracking.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <optional>

namespace saccade {
namespace {

// Built once: the scene, the model's description and the fovea on the target.
struct Fixture {
  Fixture() : demo(MakeDemoCase(/*seed=*/5)) {
    std::string error;
    model.emplace(*DescribeModel(demo.model, options, &error));
    fovea_m = demo.truth * ShapeCentre(TargetShape());
    query.fovea_m = fovea_m;
    query.intrinsics = CameraIntrinsics{};
  }
  CrossCaptureCase demo;
  RecognitionOptions options;
  std::optional<ModelDescription> model;
  Eigen::Vector3f fovea_m;
  SceneQuery query;
};

const Fixture& Demo() {
  static const Fixture fixture;
  return fixture;
}

void BM_FoveateIndices(benchmark::State& state) {
  const Fixture& f = Demo();
  const Box bounds = *BoundingBox(f.demo.scene.cloud);
  const FoveaGeometry g = ComputeFoveaGeometry(f.query.fovea, bounds, f.fovea_m);
  const CameraIntrinsics k;
  for (auto _ : state)
    benchmark::DoNotOptimize(FoveateIndices(f.demo.scene.cloud, f.query.fovea, g, 0, &k));
}
BENCHMARK(BM_FoveateIndices)->Unit(benchmark::kMillisecond);

// Recognition at the fovea grown by G (state.range(0), centimetres on every axis): 0 is a
// tracking frame's fovea, the others what a lost target makes. Counters: the keypoints
// described and the instances found.
void BM_Recognize(benchmark::State& state) {
  const Fixture& f = Demo();
  SceneQuery q = f.query;
  q.fovea.growth_m = Eigen::Vector3f::Constant(float(state.range(0)) / 100);
  RecognitionResult r;
  for (auto _ : state) r = Recognize(*f.model, f.demo.scene.cloud, q, f.options);
  state.counters["keypoints"] = double(r.stats.TotalKeypoints());
  state.counters["instances"] = double(r.instances.size());
}
BENCHMARK(BM_Recognize)
    ->ArgName("G_cm")
    ->Arg(0)
    ->Arg(20)
    ->Arg(50)
    ->Arg(100)
    ->Unit(benchmark::kMillisecond);

// A frame of tracking: the true pose nudged 1 cm, refined against the frame.
void BM_TrackPose(benchmark::State& state) {
  const Fixture& f = Demo();
  const Eigen::Matrix4f start = (Eigen::Translation3f(0.01f, 0, 0) * f.demo.truth).matrix();
  for (auto _ : state)
    benchmark::DoNotOptimize(TrackPose(f.model->verification(), f.demo.scene.cloud,
                                       CameraIntrinsics{}, start, TrackOptions{}));
}
BENCHMARK(BM_TrackPose)->Unit(benchmark::kMillisecond);

// A search frame's whole-frame candidates (the table removed, model-sized windows scored).
void BM_Candidates(benchmark::State& state) {
  const Fixture& f = Demo();
  const ModelSignature signature = SignModel(*f.model);
  std::size_t n = 0;
  for (auto _ : state)
    n = ProposeCandidates(f.demo.scene.cloud, CameraIntrinsics{}, signature, CandidateOptions{})
            .size();
  state.counters["candidates"] = double(n);
}
BENCHMARK(BM_Candidates)->Unit(benchmark::kMillisecond);

void BM_DescribeModel(benchmark::State& state) {
  const Fixture& f = Demo();
  for (auto _ : state) benchmark::DoNotOptimize(DescribeModel(f.demo.model, f.options, nullptr));
}
BENCHMARK(BM_DescribeModel)->Unit(benchmark::kMillisecond);

// Saccade's own depth-to-colour registration of one 640x480 frame (a sensor that does not
// register, and the Kinect's raw disparity through freenect://): the nominal Kinect layout.
void BM_RegisterDepth(benchmark::State& state) {
  const Fixture& f = Demo();
  const ColourCalibration c = NominalKinectCalibration();
  std::vector<std::uint16_t> depth(f.demo.scene.cloud.size(), 0);
  for (std::size_t i = 0; i < depth.size(); ++i) {
    const float z = f.demo.scene.cloud[i].z;
    if (std::isfinite(z)) depth[i] = static_cast<std::uint16_t>(z * 1000.0f);
  }
  for (auto _ : state)
    benchmark::DoNotOptimize(RegisterDepth(depth.data(), c.depth, c.colour_from_depth, c.colour));
}
BENCHMARK(BM_RegisterDepth)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace saccade

BENCHMARK_MAIN();
