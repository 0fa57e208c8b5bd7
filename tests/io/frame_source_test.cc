// Frame sources: spec parsing, the synthetic scenarios and their ground truth, PCD and depth
// sequences written by FrameWriter and read back, the live mailbox, and bad input.
#include "io/sources/frame_source.h"
#include "core/sim/scenario.h"

#include "io/formats/cloud_io.h"
#include "io/formats/frame_writer.h"
#include "io/formats/images.h"
#include "io/sources/mailbox.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace saccade {
namespace {

namespace fs = std::filesystem;

std::string FreshDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "saccade_" + name + "_" + std::to_string(getpid());
  fs::remove_all(dir);
  return dir;
}

std::vector<Frame> ReadAll(FrameSource& source) {
  std::vector<Frame> frames;
  Frame f;
  std::string error;
  for (;;) {
    const auto s = source.Next(&f, &error);
    if (s == FrameSource::Status::kEnd) break;
    EXPECT_EQ(s, FrameSource::Status::kFrame) << error;
    if (s != FrameSource::Status::kFrame) break;
    frames.push_back(f);
  }
  return frames;
}

std::vector<Frame> Open(const std::string& spec) {
  std::string error;
  auto source = OpenSource(spec, &error);
  EXPECT_TRUE(source) << error;
  return source ? ReadAll(*source) : std::vector<Frame>{};
}

std::string OpenError(const std::string& spec) {
  std::string error;
  auto source = OpenSource(spec, &error);
  EXPECT_FALSE(source) << spec;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  return error;
}

TEST(SourceSpec, KindsTargetsAndOptions) {
  std::string error;
  auto s = ParseSourceSpec("synthetic:circular?frames=3&seed=9", &error);
  ASSERT_TRUE(s) << error;
  EXPECT_EQ(s->kind, "synthetic");
  EXPECT_EQ(s->target, "circular");
  EXPECT_EQ(s->options.at("frames"), "3");
  EXPECT_EQ(s->options.at("seed"), "9");
  EXPECT_EQ(ParseSourceSpec("openni2://#1", &error)->target, "#1");
  EXPECT_EQ(ParseSourceSpec("/a/b.oni?mode=step", &error)->kind, "oni");
  EXPECT_EQ(ParseSourceSpec("depth:/x", &error)->kind, "depth");
  EXPECT_FALSE(ParseSourceSpec("webcam:0", &error));
  EXPECT_NE(error.find("unknown kind 'webcam'"), std::string::npos) << error;
  EXPECT_FALSE(ParseSourceSpec("pcd:/x?rate", &error));
  EXPECT_FALSE(ParseSourceSpec("nonsense", &error));
}

TEST(SourceSpec, BadOptionsAndMissingFoldersAreOneLineErrors) {
  EXPECT_NE(OpenError("synthetic:static?speed=2").find("unknown option 'speed'"),
            std::string::npos);
  EXPECT_NE(OpenError("synthetic:static?rate=fast").find("rate=fast"), std::string::npos);
  EXPECT_NE(OpenError("synthetic:nowhere").find("no such scenario"), std::string::npos);
  EXPECT_NE(OpenError("pcd:/nonexistent/dir").find("/nonexistent/dir"), std::string::npos);
  const std::string empty = FreshDir("empty");
  fs::create_directories(empty);
  EXPECT_NE(OpenError("depth:" + empty).find("no depth image"), std::string::npos);
  EXPECT_NE(OpenError("/nonexistent/x.oni").find("/nonexistent/x.oni"), std::string::npos);
}

TEST(SyntheticSource, FiniteSequenceWithClockSequenceNumbersAndTruth) {
  const auto frames = Open("synthetic:linear?rate=0&frames=4");
  ASSERT_EQ(frames.size(), 4u);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].sequence, i);
    EXPECT_EQ(frames[i].capture_utime, static_cast<std::int64_t>(std::llround(i * 1e6 / 30)));
    ASSERT_TRUE(frames[i].truth);
    EXPECT_EQ(frames[i].cloud->width, 640u);
    EXPECT_EQ(frames[i].intrinsics.fx, 525.0);
  }
  // The linear preset moves the target 10 cm/s along x.
  const float dx = frames[3].truth->centroid_m.x() - frames[0].truth->centroid_m.x();
  EXPECT_NEAR(dx, 0.1f * 3 / 30, 1e-4);
}

TEST(SyntheticSource, LoopContinuesSequenceAndClock) {
  std::string error;
  auto source = OpenSource("synthetic:static?rate=0&frames=2&loop=1", &error);
  ASSERT_TRUE(source) << error;
  Frame f;
  for (int i = 0; i < 5; ++i) ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame);
  EXPECT_EQ(f.sequence, 4u);
  EXPECT_EQ(f.capture_utime, std::llround(4 * 1e6 / 30));
  source->Stop();
  EXPECT_EQ(source->Next(&f, &error), FrameSource::Status::kEnd);

  // The scenario's own clock, not the 30 Hz default: the paper protocol shows a scene a second.
  source = OpenSource("synthetic:paper-protocol?rate=0&frames=2&loop=1", &error);
  ASSERT_TRUE(source) << error;
  for (int i = 0; i < 3; ++i) ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame);
  EXPECT_EQ(f.capture_utime, 2000000);
}

TEST(Scenarios, TrajectoriesAndVisibility) {
  auto occluded = ScenarioPreset("occluded");
  ASSERT_TRUE(occluded);
  const float before = RenderScenarioFrame(*occluded, 10).truth.visible_fraction;
  const float during =
      RenderScenarioFrame(*occluded, occluded->occluded_from + 5).truth.visible_fraction;
  EXPECT_GT(before, 0.6f);
  EXPECT_LT(during, 0.1f);

  auto leave = ScenarioPreset("leave-return");
  ASSERT_TRUE(leave);
  const ScenarioFrame start = RenderScenarioFrame(*leave, 0);
  const ScenarioFrame away = RenderScenarioFrame(*leave, 60);  // t = 2 s: furthest out
  const ScenarioFrame back = RenderScenarioFrame(*leave, 119);
  EXPECT_GT(start.truth.visible_fraction, 0.6f);
  EXPECT_EQ(away.truth.visible_fraction, 0.0f);
  EXPECT_GT(back.truth.visible_fraction, 0.6f);
  EXPECT_NEAR((back.truth.centroid_m - start.truth.centroid_m).norm(), 0.0f, 0.02f);

  auto circle = ScenarioPreset("circular");
  ASSERT_TRUE(circle);
  for (int i : {0, 45, 90, 135}) {
    const Eigen::Vector2f xz = circle->target_motion.PositionAt(i / circle->rate_hz);
    EXPECT_NEAR((xz - circle->target_motion.centre_xz_m).norm(), 0.2f, 1e-5);
  }
}

TEST(Scenarios, YamlFileStartsFromAPresetAndIsStrict) {
  const std::string path = ::testing::TempDir() + "fast_linear.yaml";
  std::ofstream(path) << "preset: linear\nname: fast\nframes: 3\n"
                         "target_motion:\n  velocity_xz_mps: [0.3, 0]\nnoise:\n  enabled: false\n";
  const auto frames = Open("synthetic:" + path + "?rate=0");
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_NEAR(frames[2].truth->centroid_m.x() - frames[0].truth->centroid_m.x(), 0.3f * 2 / 30,
              1e-4);
  const std::string bad = ::testing::TempDir() + "bad_scenario.yaml";
  std::ofstream(bad) << "preset: linear\ntarget_motion:\n  speed: 3\n";
  const std::string error = OpenError("synthetic:" + bad);
  EXPECT_NE(error.find("bad_scenario.yaml: key 'target_motion.speed': unknown key"),
            std::string::npos)
      << error;
}

TEST(Scenarios, PaperProtocolClutterGrowsAroundAVisibleBall) {
  auto protocol = ScenarioPreset("paper-protocol");
  ASSERT_TRUE(protocol);
  ASSERT_EQ(protocol->frames, 12);
  std::size_t last_labels = 0;
  for (int i = 0; i < 12; ++i) {
    const ScenarioFrame f = RenderScenarioFrame(*protocol, i);
    std::vector<std::uint32_t> labels(f.rendered.label);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    EXPECT_GE(labels.size(), last_labels) << "frame " << i;
    last_labels = labels.size();
    EXPECT_GT(f.truth.visible_fraction, 0.5f) << "frame " << i;
  }
  EXPECT_GE(last_labels, 10u);  // background, ball and most of the 11 clutter objects in view
}

TEST(Mailbox, KeepsTheLatestAndCountsWhatWasOverwritten) {
  LatestMailbox<int> box;
  box.Put(1);
  box.Put(2);
  box.Put(3);
  EXPECT_EQ(box.Take(), 3);
  EXPECT_EQ(box.dropped(), 2u);
  box.Put(4);
  box.Close();
  box.Put(5);  // ignored once closed
  EXPECT_EQ(box.Take(), 4);
  EXPECT_EQ(box.Take(), std::nullopt);
}

TEST(LiveSource, EveryFrameIsTakenOrCountedAsDropped) {
  std::string error;
  auto source = OpenSource("synthetic:static?rate=1000&frames=6", &error);
  ASSERT_TRUE(source) << error;
  EXPECT_TRUE(source->Live());
  const auto frames = ReadAll(*source);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().sequence, 5u);  // the last frame is never lost
  const SourceStats stats = source->Stats();
  EXPECT_EQ(stats.produced, 6u);
  EXPECT_EQ(frames.size() + stats.dropped, 6u);
  EXPECT_EQ(stats.state, "ended");
}

void ExpectSameFrames(const std::vector<Frame>& a, const std::vector<Frame>& b, float tol_m) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t f = 0; f < a.size(); ++f) {
    ASSERT_EQ(a[f].cloud->size(), b[f].cloud->size());
    int finite = 0;
    for (std::size_t i = 0; i < a[f].cloud->size(); ++i) {
      const auto& p = (*a[f].cloud)[i];
      const auto& q = (*b[f].cloud)[i];
      ASSERT_EQ(std::isfinite(p.z), std::isfinite(q.z)) << "frame " << f << " pixel " << i;
      if (!std::isfinite(p.z)) continue;
      ++finite;
      ASSERT_LE((p.getVector3fMap() - q.getVector3fMap()).norm(), tol_m);
    }
    EXPECT_GT(finite, 50000);
    ASSERT_TRUE(a[f].truth && b[f].truth);
    EXPECT_LT((a[f].truth->centroid_m - b[f].truth->centroid_m).norm(), 1e-6);
    EXPECT_TRUE(a[f].truth->target_pose.isApprox(b[f].truth->target_pose, 1e-6f));
  }
}

TEST(FileSources, DepthAndPcdRecordingsReadBackWithTheirTruth) {
  const auto original = Open("synthetic:circular?rate=0&frames=3");
  for (const auto format : {FrameWriter::Format::kDepth, FrameWriter::Format::kPcd}) {
    const bool depth = format == FrameWriter::Format::kDepth;
    const std::string dir = FreshDir(depth ? "depth" : "pcd");
    std::string error;
    auto writer = FrameWriter::Open(dir, format, &error);
    ASSERT_TRUE(writer) << error;
    for (const auto& f : original) ASSERT_TRUE(writer->Write(f, &error)) << error;
    const auto back = Open((depth ? "depth:" : "pcd:") + dir);
    // Depth images hold millimetres: 0.5 mm of rounding, scaled along the ray.
    ExpectSameFrames(original, back, depth ? 0.0011f : 0.0f);
    if (depth) {
      EXPECT_EQ(back[0].intrinsics.cx, 319.5);
    }
  }
}

// Writes the frames as a PCD recording into `dir`; its .pcd files in name order.
std::vector<std::string> WritePcdRecording(const std::vector<Frame>& frames,
                                           const std::string& dir) {
  std::string error;
  auto writer = FrameWriter::Open(dir, FrameWriter::Format::kPcd, &error);
  EXPECT_TRUE(writer) << error;
  for (const auto& f : frames) {
    if (writer) {
      EXPECT_TRUE(writer->Write(f, &error)) << error;
    }
  }
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".pcd") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// A recording with a corrupt and a truncated file: those frames are skipped and counted (their
// sequence numbers unused), the others read with their own truth; a folder where no frame is
// usable is one error, not a loop without end.
TEST(FileSources, UnusableFramesAreSkippedAndCountedAndAFolderOfNoneIsAnError) {
  const auto original = Open("synthetic:circular?rate=0&frames=4");
  const std::string dir = FreshDir("unusable");
  std::string error;
  const std::vector<std::string> files = WritePcdRecording(original, dir);
  ASSERT_EQ(files.size(), 4u);
  std::ofstream(files[1], std::ios::trunc) << "garbage";
  fs::resize_file(files[3], fs::file_size(files[3]) / 2);

  for (const bool loop : {false, true}) {
    auto source = OpenSource("pcd:" + dir + (loop ? "?loop=1" : ""), &error);
    ASSERT_TRUE(source) << error;
    std::vector<Frame> back;
    Frame f;
    while (back.size() < (loop ? 4u : 10u) &&
           source->Next(&f, &error) == FrameSource::Status::kFrame)
      back.push_back(f);
    ASSERT_EQ(back.size(), loop ? 4u : 2u) << error;
    const std::vector<std::int64_t> expected = {0, 2, 4, 6};
    for (std::size_t i = 0; i < back.size(); ++i) {
      EXPECT_EQ(back[i].sequence, expected[i]);
      ExpectSameFrames({original[i % 2 * 2]}, {back[i]}, 0.0f);
    }
    EXPECT_EQ(source->Stats().skipped, loop ? 3u : 2u);  // the loop met file 2 again
  }

  std::ofstream(files[0], std::ios::trunc) << "garbage";
  std::ofstream(files[2], std::ios::trunc);
  auto none = OpenSource("pcd:" + dir + "?loop=1", &error);
  ASSERT_TRUE(none) << error;
  Frame f;
  EXPECT_EQ(none->Next(&f, &error), FrameSource::Status::kError);
  EXPECT_NE(error.find("no frame of pcd:" + dir), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

// pcd: takes one PCD file as well as a folder: a sequence of one frame, repeated with loop=1.
TEST(FileSources, APcdSourceTakesASingleFile) {
  const auto original = Open("synthetic:static?rate=0&frames=2");
  const std::string dir = FreshDir("single");
  std::string error;
  const std::vector<std::string> files = WritePcdRecording(original, dir);
  ASSERT_EQ(files.size(), 2u);
  for (const bool loop : {false, true}) {
    auto source = OpenSource("pcd:" + files[1] + (loop ? "?loop=1" : ""), &error);
    ASSERT_TRUE(source) << error;
    std::vector<Frame> back;
    Frame f;
    while (back.size() < 3u && source->Next(&f, &error) == FrameSource::Status::kFrame)
      back.push_back(f);
    ASSERT_EQ(back.size(), loop ? 3u : 1u) << error;
    for (const Frame& b : back) ExpectSameFrames({original[1]}, {b}, 0.0f);
  }
  // A file that is not a PCD is neither a folder nor a recording.
  std::ofstream(dir + "/notes.txt") << "x";
  EXPECT_FALSE(OpenSource("pcd:" + dir + "/notes.txt", &error));
  EXPECT_NE(error.find("notes.txt: no such folder or .pcd file"), std::string::npos) << error;
}

TEST(FileSources, ACorruptFileAloneInASequenceIsAnErrorNamingIt) {
  const std::string dir = FreshDir("corrupt");
  fs::create_directories(dir);
  IntrinsicsFile k{525, 525, 319.5, 239.5, 640, 480};
  std::string error;
  ASSERT_TRUE(WriteIntrinsicsFile(dir + "/intrinsics.yaml", k, &error));
  std::ofstream(dir + "/depth_000000.png") << "garbage";
  auto source = OpenSource("depth:" + dir, &error);
  ASSERT_TRUE(source) << error;
  Frame f;
  EXPECT_EQ(source->Next(&f, &error), FrameSource::Status::kError);
  EXPECT_NE(error.find("depth_000000.png"), std::string::npos) << error;
}

// The real Kinect frames shipped as both 16-bit TIFF depth and PCD: the depth source must give
// the same points as the PCD.
TEST(FileSources, RealKinectTiffDepthMatchesItsPcd) {
  SACCADE_REQUIRE_DATA("pcl_test/grabber_sequences/tiff");
  const std::string k_path = ::testing::TempDir() + "grabber_intrinsics.yaml";
  std::string error;
  ASSERT_TRUE(WriteIntrinsicsFile(k_path, {525, 525, 320, 240, 640, 480}, &error));
  const auto depth = Open("depth:" + testing::DataPath("pcl_test/grabber_sequences/tiff") +
                          "?intrinsics=" + k_path);
  const auto pcd = Open("pcd:" + testing::DataPath("pcl_test/grabber_sequences/pcd"));
  ASSERT_EQ(depth.size(), 3u);
  ASSERT_EQ(pcd.size(), 3u);
  for (std::size_t f = 0; f < 3; ++f) {
    int compared = 0, close = 0;
    for (std::size_t i = 0; i < depth[f].cloud->size(); ++i) {
      const auto& p = (*depth[f].cloud)[i];
      const auto& q = (*pcd[f].cloud)[i];
      if (!std::isfinite(p.z) || !std::isfinite(q.z)) continue;
      ++compared;
      close += (p.getVector3fMap() - q.getVector3fMap()).norm() < 0.005f;
    }
    EXPECT_GT(compared, 100000);
    EXPECT_GT(close, compared * 99 / 100) << "frame " << f;
    EXPECT_NE((*depth[f].cloud)[320 * 640 + 320].r + (*depth[f].cloud)[320 * 640 + 320].g, 0)
        << "colour from the _rgb.tiff partner";
  }
}

// A real capture re-rendered (capture:FILE.yaml): at t = 0 with nothing moving it is the
// capture itself with the identity as the object's pose; as the camera moves, the truth is the
// camera's motion undone, and the object's points are where that pose puts them.
TEST(CaptureSource, RendersARealCaptureFromAMovingCameraWithExactTruth) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const std::string yaml = ::testing::TempDir() + "capture-seq.yaml";
  std::ofstream(yaml) << "capture: mosd_xcap/test/test31.pcd\nobject: 3\nframes: 4\nrate_hz: 30\n"
                         "camera_motion: {kind: linear, velocity_xz_mps: [0.3, 0.0]}\n";
  std::string error;
  auto source = OpenSource("capture:" + yaml + "?rate=0&data=" + testing::DataPath(""), &error);
  ASSERT_TRUE(source) << error;
  std::optional<LabelledCloud> capture =
      LoadLabelledCloud(testing::DataPath("mosd_xcap/test/test31.pcd"), &error);
  ASSERT_TRUE(capture) << error;
  Frame first, last;
  ASSERT_EQ(source->Next(&first, &error), FrameSource::Status::kFrame) << error;
  for (int i = 1; i < 4; ++i) ASSERT_EQ(source->Next(&last, &error), FrameSource::Status::kFrame);
  EXPECT_EQ(source->Next(&last, &error) == FrameSource::Status::kFrame, false);  // 4 frames
  ASSERT_TRUE(first.truth && last.truth);
  EXPECT_TRUE(first.truth->target_pose.isApprox(Eigen::Isometry3f::Identity()));
  EXPECT_GT(first.truth->visible_fraction, 0.95f);
  std::size_t same = 0, finite = 0;
  for (std::size_t i = 0; i < first.cloud->size(); ++i) {
    if (!FinitePoint(capture->cloud[i])) continue;
    ++finite;
    same +=
        FinitePoint((*first.cloud)[i]) &&
        ((*first.cloud)[i].getVector3fMap() - capture->cloud[i].getVector3fMap()).norm() < 1e-3f;
  }
  EXPECT_GT(same, finite * 99 / 100);
  // Frame 3 at 30 Hz: the camera is 3 cm to the right, so the object sits 3 cm to its left.
  const Eigen::Vector3f moved = last.truth->target_pose.translation();
  EXPECT_NEAR(moved.x(), -0.03f, 1e-4f);
  EXPECT_NEAR(moved.y(), 0.0f, 1e-5f);
  EXPECT_NEAR(moved.z(), 0.0f, 1e-5f);
  EXPECT_EQ(last.capture_utime, 100000);
}

TEST(CaptureSource, AnOccluderHidesTheObjectForItsFramesOnly) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const std::string yaml = ::testing::TempDir() + "capture-occluded.yaml";
  std::ofstream(yaml) << "capture: mosd_xcap/test/test31.pcd\nobject: 3\nframes: 3\n"
                         "occluded_from: 1\noccluded_frames: 1\noccluder_size_m: [0.4, 0.4]\n";
  std::string error;
  auto source = OpenSource("capture:" + yaml + "?rate=0&data=" + testing::DataPath(""), &error);
  ASSERT_TRUE(source) << error;
  std::vector<float> visible;
  Frame f;
  while (source->Next(&f, &error) == FrameSource::Status::kFrame) {
    visible.push_back(f.truth->visible_fraction);
    if (visible.size() == 2) {  // the board is nearer than the object, at its centroid's pixel
      const Eigen::Vector2d uv = f.intrinsics.Project(f.truth->centroid_m);
      const PointT& p = f.cloud->at(int(std::lround(uv.x())), int(std::lround(uv.y())));
      ASSERT_TRUE(FinitePoint(p));
      EXPECT_NEAR(p.z, f.truth->centroid_m.norm() - 0.15f, 0.05f);
    }
  }
  ASSERT_EQ(visible.size(), 3u);
  EXPECT_GT(visible[0], 0.95f);
  EXPECT_LT(visible[1], 0.05f);
  EXPECT_GT(visible[2], 0.95f);
}

TEST(CaptureSource, AMissingObjectIsOneErrorNamingTheFile) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const std::string yaml = ::testing::TempDir() + "capture-missing.yaml";
  std::ofstream(yaml) << "capture: mosd_xcap/test/test31.pcd\nobject: 99\n";
  std::string error;
  EXPECT_FALSE(OpenSource("capture:" + yaml + "?data=" + testing::DataPath(""), &error));
  EXPECT_NE(error.find("test31.pcd: no object 99"), std::string::npos) << error;
  std::ofstream(yaml) << "capture: x.pcd\nobjekt: 1\n";
  EXPECT_FALSE(OpenSource("capture:" + yaml, &error));
  EXPECT_NE(error.find("key 'objekt': unknown key"), std::string::npos) << error;
}

}  // namespace
}  // namespace saccade
