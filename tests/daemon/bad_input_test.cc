// The bad-input corpus (issue 21): files, flags, source specs and configurations that are wrong
// in the ways real ones are, each given to the real `saccade` or `saccaded` binary. Every case
// asserts the exit code (1: input could not be processed, 2: bad usage), one line on stderr
// saying what is wrong (the case's `says` is a part of it), nothing on stdout and nothing
// written: the case's folder holds exactly the files it started with. The LCM messages of the
// corpus are in tests/io/command_test.cc, the PCD files checked one by one in
// tests/io/pcd_check_test.cc; docs/RELIABILITY.md counts them all.
#include "support/test_data.h"

#include <gtest/gtest.h>
#include <png.h>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct File {
  std::string name;     // relative to the case's folder; a trailing '/' makes a folder
  std::string content;  // the bytes
};

struct BadInput {
  std::string name;         // the test's name
  std::vector<File> files;  // written into the case's folder $D before the run
  std::string command;      // saccade's (or, starting with "saccaded ", saccaded's) arguments
  int code;                 // the exit code expected
  std::string says;         // a part of the one line expected on stderr ($D: the folder)
};

// ---- file contents ----------------------------------------------------------------------

std::string Pcd(const std::string& fields, const std::string& size, const std::string& type,
                const std::string& count, int points, const std::string& data_kind,
                const std::string& body) {
  const std::string n = std::to_string(points);
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + size + "\nTYPE " + type +
         "\nCOUNT " + count + "\nWIDTH " + n + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + n +
         "\nDATA " + data_kind + "\n" + body;
}

// A good little ASCII cloud: three points of a 1 cm triangle.
std::string GoodPcd() {
  return Pcd("x y z", "4 4 4", "F F F", "1 1 1", 3, "ascii", "0 0 1\n0.01 0 1\n0 0.01 1\n");
}

std::string PngFile(png_uint_32 format, int width, int height) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(width);
  png.height = static_cast<png_uint_32>(height);
  png.format = format;
  std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(png), 7);
  png_alloc_size_t size = 0;
  png_image_write_to_memory(&png, nullptr, &size, 0, pixels.data(), 0, nullptr);
  std::string bytes(size, '\0');
  png_image_write_to_memory(&png, bytes.data(), &size, 0, pixels.data(), 0, nullptr);
  bytes.resize(size);
  return bytes;
}

const std::string kIntrinsics = "width: 4\nheight: 3\nfx: 525\nfy: 525\ncx: 2\ncy: 1.5\n";
const std::string kPngMagic = "\x89PNG\r\n\x1a\n";
const std::string kBom = "\xef\xbb\xbf";
const std::string kConfigs = "configurations: [{name: a}]\n";

std::string Scenario(const std::string& extra) { return "preset: static\n" + extra; }

// Little-endian fields, as .oni files hold them.
struct Bytes {
  std::string s;
  Bytes& U8(unsigned v) { return s += static_cast<char>(v & 0xFF), *this; }
  Bytes& U32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) U8(v >> (8 * i));
    return *this;
  }
  Bytes& U64(std::uint64_t v) { return U32(static_cast<std::uint32_t>(v)).U32(v >> 32); }
  Bytes& Text(const std::string& t) { return s += t, *this; }
  Bytes& Name(const std::string& t) {
    return U32(static_cast<std::uint32_t>(t.size() + 1)).Text(t).U8(0);
  }
};

// The start of an .oni as openni::Recorder writes one: the file header, the depth node added
// (16z codec, 4 frames) and three of its integer properties, each record a 28-byte header and
// its fields. `last_property` names the last property (xnDeviceMaxDepth in a true file): a
// crafted file whose name has bytes over 127 made Debian's libOniFile crash.
std::string OniStart(const std::string& last_property) {
  Bytes oni;
  oni.Text("NI10").U8(1).U8(0).U8(1).U8(0).U32(0);  // version 1.0.1.0
  oni.U64(~0ull).U32(2);                            // no timestamp yet; the largest node id
  const auto record = [&oni](std::uint32_t type, const Bytes& fields) {
    oni.U32(0x0052494E).U32(type).U32(1);  // "NIR\0", the record's type, node 1
    oni.U32(static_cast<std::uint32_t>(28 + fields.s.size())).U32(0).U64(0).Text(fields.s);
  };
  record(0x0D, Bytes().Name("Depth").U32(2).Text("16zT").U32(4).U64(0).U64(100000).U64(0));
  const auto property = [&](const std::string& name, std::uint64_t value) {
    record(0x03, Bytes().Name(name).U32(8).U64(value));
  };
  property("oniRequiredFrameSize", 614400);
  property("xnIsGenerating", 1);
  property(last_property, 10000);
  return oni.s;
}

// ---- the corpus -------------------------------------------------------------------------

std::vector<BadInput> Corpus() {
  const std::string good = GoodPcd();
  const std::vector<File> model_ok = {{"m.pcd", good}};
  std::vector<BadInput> c;
  auto add = [&c](std::string name, std::vector<File> files, std::string command, int code,
                  std::string says) {
    c.push_back({std::move(name), std::move(files), std::move(command), code, std::move(says)});
  };
  auto scene = [&](const std::string& name, const std::string& bytes, const std::string& says) {
    add("Scene" + name, {{"m.pcd", good}, {"s.pcd", bytes}},
        "recognize --model $D/m.pcd --scene $D/s.pcd --plain", 1, says);
  };
  auto model = [&](const std::string& name, const std::string& bytes, const std::string& says) {
    add("Model" + name, {{"m.pcd", bytes}, {"s.pcd", good}},
        "recognize --model $D/m.pcd --scene $D/s.pcd --fovea 0,0,1", 1, says);
  };

  // PCD files given to every command that reads one.
  scene("Empty", "", "$D/s.pcd: empty file, not a PCD file");
  scene("IsAPng", PngFile(PNG_FORMAT_GRAY, 2, 2), "$D/s.pcd: not a PCD file");
  scene("RandomBytes", std::string("\x13\xf7\x00\x99\x42\x17\x80\xff", 8) + "abc",
        "$D/s.pcd: not a PCD file");
  scene("StartsWithAUtf8Bom", kBom + good, "$D/s.pcd: not a PCD file");
  scene("HugeWidth",
        Pcd("x y z", "4 4 4", "F F F", "1 1 1", 3, "ascii", "0 0 1\n")
            .replace(good.find("WIDTH 3"), 7, "WIDTH 4000000000"),
        "$D/s.pcd");
  scene("DoubleXyz", Pcd("x y z", "8 8 8", "F F F", "1 1 1", 1, "ascii", "0 0 1\n"), "$D/s.pcd");
  scene("IntXyz", Pcd("x y z", "4 4 4", "I I I", "1 1 1", 1, "ascii", "0 0 1\n"), "$D/s.pcd");
  scene("UnknownType", Pcd("x y z", "4 4 4", "F Q F", "1 1 1", 1, "ascii", "0 0 1\n"), "$D/s.pcd");
  scene("CountThree", Pcd("x y z", "4 4 4", "F F F", "3 1 1", 1, "ascii", "0 0 0 0 1\n"),
        "$D/s.pcd");
  scene("NegativeSize", Pcd("x y z", "-4 4 4", "F F F", "1 1 1", 1, "ascii", "0 0 1\n"),
        "$D/s.pcd");
  scene("AWordInTheData", Pcd("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii", "0 0 1\n0 zero 1\n"),
        "$D/s.pcd");
  scene("TooFewValues", Pcd("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii", "0 0 1\n0 1\n"),
        "$D/s.pcd");
  scene("TruncatedBinary", Pcd("x y z", "4 4 4", "F F F", "1 1 1", 100, "binary", "0123"),
        "$D/s.pcd");
  scene("NoDataLine", good.substr(0, good.find("DATA")), "$D/s.pcd");
  scene("UnknownDataKind", Pcd("x y z", "4 4 4", "F F F", "1 1 1", 1, "zipped", "0 0 1\n"),
        "$D/s.pcd");
  scene("CompressedSizesThatLie",
        Pcd("x y z", "4 4 4", "F F F", "1 1 1", 1000, "binary_compressed",
            std::string("\x10\x00\x00\x00\xff\xff\xff\x7f", 8) + "0123456789abcdef"),
        "$D/s.pcd");
  scene("NoFields", Pcd("", "", "", "", 1, "ascii", "0 0 1\n"), "$D/s.pcd");
  scene("NoZ", Pcd("x y", "4 4", "F F", "1 1", 1, "ascii", "0 0\n"), "$D/s.pcd");
  scene("OnlyNaN", Pcd("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii", "nan nan nan\nnan 0 1\n"),
        "$D/s.pcd");
  model("Empty", "", "$D/m.pcd: empty file, not a PCD file");
  model("IsText", "hello, world\n", "$D/m.pcd: not a PCD file");
  model("WidthTimesHeightDisagree",
        Pcd("x y z", "4 4 4", "F F F", "1 1 1", 3, "ascii", "0 0 1\n")
            .replace(good.find("HEIGHT 1"), 8, "HEIGHT 2"),
        "$D/m.pcd");
  model("IsAFolder", {}, "$D/m.pcd");
  c.back().files = {{"m.pcd/", ""}, {"s.pcd", good}};
  add("ModelMissing", {{"s.pcd", good}},
      "recognize --model $D/nothing.pcd --scene $D/s.pcd --plain", 1, "$D/nothing.pcd");
  add("ModelIsADevice", {{"s.pcd", good}}, "recognize --model /dev/zero --scene $D/s.pcd --plain",
      1, "/dev/zero: not a regular file");
  add("BenchCorruptModel", {{"m.pcd", "PK\x03\x04"}, {"s.pcd", good}},
      "bench --model $D/m.pcd --scene $D/s.pcd --fovea 0,0,1", 1, "$D/m.pcd: not a PCD file");
  add("SegmentEmptyScene", {{"s.pcd", ""}}, "segment --scene $D/s.pcd --out $D/o.pcd", 1,
      "$D/s.pcd: empty file, not a PCD file");
  add("SegmentMissingScene", {}, "segment --scene $D/s.pcd --out $D/o.pcd", 1, "$D/s.pcd");
  add("SegmentDoubleScene",
      {{"s.pcd", Pcd("x y z", "8 8 8", "F F F", "1 1 1", 1, "ascii", "0 0 1\n")}},
      "segment --scene $D/s.pcd --out $D/o.pcd", 1, "$D/s.pcd");
  add("EvalCorruptDatasetFile", {{"m.pcd", good}, {"s.pcd", "VERSION 0.7\n"}, {"c.yaml", kConfigs}},
      "eval --dataset $D/s.pcd --model $D/m.pcd --configs $D/c.yaml --out $D/out", 1, "$D/s.pcd");
  add("EvalCorruptModel", {{"m.pcd", kPngMagic}, {"s.pcd", good}, {"c.yaml", kConfigs}},
      "eval --dataset $D/s.pcd --model $D/m.pcd --configs $D/c.yaml --out $D/out", 1, "$D/m.pcd");

  // Flags.
  add("UnknownCommand", {}, "recognise --model m.pcd", 2, "unknown command 'recognise'");
  add("UnknownFlag", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --plain --fast", 2,
      "--fast");
  add("FlagWithoutItsValue", {}, "recognize --plain --model", 2, "--model");
  add("StrayArgument", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --plain extra", 2,
      "extra");
  add("MissingScene", model_ok, "recognize --model $D/m.pcd --plain", 2, "missing --scene");
  add("FoveaOfTwoNumbers", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --fovea 1,2", 2,
      "--fovea");
  add("FoveaBeyondFloat", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --fovea 1e39,0,0",
      2, "--fovea");
  add("FoveaNaN", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --fovea nan,0,1", 2,
      "--fovea");
  add("FoveaWords", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --fovea a,b,c", 2,
      "--fovea");
  add("ThreadsZero", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --plain --threads 0", 2,
      "--threads");
  add("ThreadsWord", model_ok, "recognize --model $D/m.pcd --scene $D/m.pcd --plain --threads many",
      2, "--threads");
  add("ThreadsHuge", model_ok,
      "recognize --model $D/m.pcd --scene $D/m.pcd --plain --threads 99999999999", 2, "--threads");
  add("BenchFramesZero", model_ok,
      "bench --model $D/m.pcd --scene $D/m.pcd --fovea 0,0,1 --frames 0", 2, "--frames");
  add("DemoSeedHuge", {}, "demo --seed 1e20", 2, "--seed");
  add("DemoSeedWord", {}, "demo --seed lucky", 2, "--seed");
  add("DemoSeedNegative", {}, "demo --seed -3", 2, "--seed");
  add("RecordFramesZero", {}, "record --source synthetic:static --out $D/out --frames 0", 2,
      "--frames");
  add("RecordFramesFraction", {}, "record --source synthetic:static --out $D/out --frames 1.5", 2,
      "--frames");
  add("RecordUnknownFormat", {}, "record --source synthetic:static --out $D/out --format mp4", 2,
      "--format");
  add("RecordWithoutOut", {}, "record --source synthetic:static", 2, "--out");
  add("SegmentZMaxNegative", model_ok, "segment --scene $D/m.pcd --out $D/o.pcd --z-max -1", 2,
      "--z-max");
  add("SegmentPlaneFractionAboveOne", model_ok,
      "segment --scene $D/m.pcd --out $D/o.pcd --plane-fraction 2", 2, "--plane-fraction");
  add("SegmentPlaneDistanceNaN", model_ok,
      "segment --scene $D/m.pcd --out $D/o.pcd --plane-distance nan", 2, "--plane-distance");
  add("SegmentMinPointsZero", model_ok, "segment --scene $D/m.pcd --out $D/o.pcd --min-points 0", 2,
      "--min-points");
  add("SegmentPickUnknown", model_ok, "segment --scene $D/m.pcd --out $D/o.pcd --pick biggest", 2,
      "--pick");
  add("SegmentSeedWord", model_ok, "segment --scene $D/m.pcd --out $D/o.pcd --seed x", 2, "--seed");
  add("EvalWithoutConfigs", model_ok, "eval --dataset $D/m.pcd --model $D/m.pcd", 2,
      "missing --configs");
  add("EvalRepeatZero", {{"m.pcd", good}, {"c.yaml", kConfigs}},
      "eval --dataset $D/m.pcd --model $D/m.pcd --configs $D/c.yaml --out $D/out --repeat 0", 2,
      "--repeat");
  add("EvalSphereRadiusNegative", {{"m.pcd", good}, {"c.yaml", kConfigs}},
      "eval --dataset $D/m.pcd --model $D/m.pcd --configs $D/c.yaml --out $D/out "
      "--sphere-radius -1",
      2, "--sphere-radius");
  add("EvalModelCentreWords", {{"m.pcd", good}, {"c.yaml", kConfigs}},
      "eval --dataset $D/m.pcd --model $D/m.pcd --configs $D/c.yaml --out $D/out "
      "--model-centre here",
      2, "--model-centre");
  add("BenchTrackRateZero", model_ok,
      "bench-track --source synthetic:static --model $D/m.pcd --rate 0", 2, "--rate");
  add("BenchTrackToleranceNegative", model_ok,
      "bench-track --source synthetic:static --model $D/m.pcd --tolerance-cm -2", 2,
      "--tolerance-cm");
  add("LogFixationsUnknownExtension", {}, "log-fixations --out $D/f.txt --count 1", 2,
      "must end in .csv or .jsonl");
  add("LogFixationsCountZero", {}, "log-fixations --out $D/f.csv --count 0", 2, "--count");
  add("FixationsWithoutLog", {}, "fixations --out $D/f.csv", 2, "lcm-logger log");
  add("FixationsLogMissing", {}, "fixations $D/nothing.lcmlog --out $D/f.csv", 1,
      "$D/nothing.lcmlog");
  add("FixationsLogNotAnLcmLog", {{"l.lcmlog", "this is not an LCM log\n"}},
      "fixations $D/l.lcmlog --out $D/f.csv", 1, "$D/l.lcmlog");
  add("FixationsLogEmpty", {{"l.lcmlog", ""}}, "fixations $D/l.lcmlog --out $D/f.csv", 1,
      "$D/l.lcmlog");
  add("FixationsLogIsAFolder", {{"l.lcmlog/", ""}}, "fixations $D/l.lcmlog --out $D/f.csv", 1,
      "$D/l.lcmlog");
  add("SaccadedUnknownFlag", {}, "saccaded --bogus", 2, "--bogus");
  add("SaccadedConfigMissing", {}, "saccaded --config $D/nothing.yaml", 2, "$D/nothing.yaml");
  // liblcm says why it refuses a URL on a line of its own; it belongs in Saccade's one line.
  add("SaccadedLcmUrlUnknownProvider", {},
      "saccaded --model synthetic:target --source synthetic:static --lcm-url bogus://x", 1,
      "cannot open LCM at 'bogus://x': LCM provider \"bogus\" not found");
  add("ViewLcmUrlNotMulticast", {}, "view --port 0 --lcm-url udpm://300.1.1.1:7667", 1,
      "Bad multicast IP address \"300.1.1.1\"");
  add("LogFixationsLcmUrlUnknownProvider", {},
      "log-fixations --out $D/f.csv --count 1 --lcm-url nope://", 1, "LCM provider \"nope\"");
  // An option liblcm cannot read is only a warning of its own: the URL is refused instead.
  add("ViewLcmUrlTtlNotANumber", {}, "view --port 0 --lcm-url 'udpm://239.255.76.67:7667?ttl=abc'",
      1, "cannot open LCM at 'udpm://239.255.76.67:7667?ttl=abc': Invalid value for ttl");
  add("ViewLcmUrlUnknownOption", {}, "view --port 0 --lcm-url 'udpm://239.255.76.67:7667?foo=1'", 1,
      ": unknown provider argument foo (");

  // Source specs.
  auto source = [&](const std::string& name, std::vector<File> files, const std::string& spec,
                    const std::string& says) {
    add("Source" + name, std::move(files), "record --source '" + spec + "' --out $D/out --frames 1",
        1, says);
  };
  source("WithoutKind", {}, "frames", "expected openni2://");
  source("UnknownKind", {}, "video:cam0", "unknown kind 'video'");
  source("KindWithoutTarget", {}, "pcd:", "expected openni2://");
  source("OptionWithoutValue", {}, "synthetic:static?loop", "option 'loop' is not key=value");
  source("EmptyOption", {}, "synthetic:static?&", "is not key=value");
  source("UnknownOption", {}, "synthetic:static?speed=2", "unknown option 'speed'");
  source("RateWord", {}, "synthetic:static?rate=fast", "option rate=fast");
  source("RateNegative", {}, "synthetic:static?rate=-30", "option rate=-30");
  source("RateTiny", {}, "synthetic:static?rate=1e-300", "rate");
  source("RateHuge", {}, "synthetic:static?rate=1e300", "rate");
  source("LoopMaybe", {}, "synthetic:static?loop=maybe", "option loop=maybe");
  source("FramesZero", {}, "synthetic:static?frames=0", "frames");
  source("FramesFraction", {}, "synthetic:static?frames=2.5", "frames");
  source("SeedHuge", {}, "synthetic:static?seed=1e20", "seed");
  source("SeedNegative", {}, "synthetic:static?seed=-1", "seed");
  source("UnknownPreset", {}, "synthetic:mars", "no such scenario");
  source("PcdFolderMissing", {}, "pcd:$D/nothing", "$D/nothing: no such folder");
  source("PcdFolderEmpty", {{"in/", ""}}, "pcd:$D/in", "$D/in: no .pcd file");
  source("PcdFolderIsAFile", {{"in", good}}, "pcd:$D/in", "$D/in: no such folder");
  source("PcdWithIntrinsics", {{"in/", ""}}, "pcd:$D/in?intrinsics=k.yaml",
         "option 'intrinsics' is for depth: sources");
  source("PcdCorruptFrame", {{"in/", ""}, {"in/0001.pcd", "\x01\x02"}}, "pcd:$D/in",
         "$D/in/0001.pcd: not a PCD file");
  source("DepthFolderWithoutImages", {{"in/", ""}, {"in/notes.txt", "x"}}, "depth:$D/in",
         "no depth image");
  source("DepthWithoutIntrinsics",
         {{"in/", ""}, {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3)}}, "depth:$D/in",
         "$D/in/intrinsics.yaml");
  source("DepthEightBit",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_GRAY, 4, 3)},
          {"in/intrinsics.yaml", kIntrinsics}},
         "depth:$D/in", "must be 16-bit grey");
  source("DepthColour",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_RGB, 4, 3)},
          {"in/intrinsics.yaml", kIntrinsics}},
         "depth:$D/in", "must be 16-bit grey");
  source("DepthTruncatedPng",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3).substr(0, 40)},
          {"in/intrinsics.yaml", kIntrinsics}},
         "depth:$D/in", "$D/in/depth_0.png");
  source("DepthPngMagicOnly",
         {{"in/", ""}, {"in/depth_0.png", kPngMagic}, {"in/intrinsics.yaml", kIntrinsics}},
         "depth:$D/in", "$D/in/depth_0.png");
  source("DepthTiffGarbage",
         {{"in/", ""}, {"in/depth_0.tiff", "II*\0garbage"}, {"in/intrinsics.yaml", kIntrinsics}},
         "depth:$D/in", "$D/in/depth_0.tiff");
  source("DepthOfAnotherSize",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 8, 3)},
          {"in/intrinsics.yaml", kIntrinsics}},
         "depth:$D/in", "$D/in/depth_0.png");
  source("IntrinsicsUnknownKey",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3)},
          {"in/intrinsics.yaml", kIntrinsics + "skew: 0\n"}},
         "depth:$D/in", "skew");
  source("IntrinsicsNegativeFocal",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3)},
          {"in/intrinsics.yaml", "width: 4\nheight: 3\nfx: -525\nfy: 525\ncx: 2\ncy: 1.5\n"}},
         "depth:$D/in", "fx");
  source("IntrinsicsZeroWidth",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3)},
          {"in/intrinsics.yaml", "width: 0\nheight: 3\nfx: 525\nfy: 525\ncx: 2\ncy: 1.5\n"}},
         "depth:$D/in", "width");
  source("IntrinsicsMissingFocal",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3)},
          {"in/intrinsics.yaml", "width: 4\nheight: 3\ncx: 2\ncy: 1.5\n"}},
         "depth:$D/in", "fx");
  source("IntrinsicsNaN",
         {{"in/", ""},
          {"in/depth_0.png", PngFile(PNG_FORMAT_LINEAR_Y, 4, 3)},
          {"in/intrinsics.yaml", "width: 4\nheight: 3\nfx: nan\nfy: 525\ncx: 2\ncy: 1.5\n"}},
         "depth:$D/in", "line 3");
  source("TruthOfAnotherLength",
         {{"in/", ""}, {"in/0001.pcd", good}, {"in/truth.csv", "frame,x\n0,1\n1,2\n"}}, "pcd:$D/in",
         "$D/in/truth.csv");
  const std::string truth_header =
      "sequence,capture_utime,tx,ty,tz,qw,qx,qy,qz,cx,cy,cz,visible_fraction\n";
  source("TruthSequenceHuge",
         {{"in/", ""},
          {"in/0001.pcd", good},
          {"in/truth.csv", truth_header + "8.9e118,0,0,0,1,1,0,0,0,0,0,1,1\n"}},
         "pcd:$D/in", "line 2: sequence and capture_utime must be whole numbers");
  source("TruthTranslationBeyondAFloat",
         {{"in/", ""},
          {"in/0001.pcd", good},
          {"in/truth.csv", truth_header + "1,0,1e39,0,1,1,0,0,0,0,0,1,1\n"}},
         "pcd:$D/in", "line 2: a number too large");
  source("TruthNotACsv", {{"in/", ""}, {"in/0001.pcd", good}, {"in/truth.csv", kPngMagic}},
         "pcd:$D/in", "$D/in/truth.csv");
  source("OniMissing", {}, "$D/nothing.oni", "$D/nothing.oni");
  source("OniNotAnOni", {{"r.oni", "not an oni file at all"}}, "$D/r.oni", "$D/r.oni");
  source("OniEmpty", {{"r.oni", ""}}, "$D/r.oni", "$D/r.oni");
  source("OniUnknownMode", {}, "$D/r.oni?mode=slow", "mode must be realtime, fast or step");
  source("OniCut", {{"r.oni", OniStart("xnDeviceMaxDepth")}}, "$D/r.oni", "$D/r.oni: cannot open");
  source("OniCraftedPropertyName", {{"r.oni", OniStart("\xff\xff\xff\xffviceMaxDepth")}},
         "$D/r.oni", "$D/r.oni: libOpenNI2 crashed playing it");
  source("Openni2UnknownRegistration", {}, "openni2://?registration=magic",
         "registration must be auto, device, saccade or none");
  source("Openni2UnknownOption", {}, "openni2://?exposure=3", "unknown option 'exposure'");
  source("FreenectRawMaybe", {}, "freenect://?raw=maybe", "option raw=maybe");
  source("FreenectUnknownOption", {}, "freenect://?led=green", "unknown option 'led'");
  source("CaptureMissing", {}, "capture:$D/nothing.yaml", "$D/nothing.yaml");
  source("CaptureUnknownKey", {{"s.yaml", "capture: a.pcd\nobject: 1\nspin: 3\n"}},
         "capture:$D/s.yaml", "spin");

  // Scenarios (synthetic:FILE.yaml).
  auto scenario = [&](const std::string& name, const std::string& yaml, const std::string& says) {
    source("Scenario" + name, {{"s.yaml", yaml}}, "synthetic:$D/s.yaml", says);
  };
  scenario("WithoutPreset", "frames: 3\n", "preset");
  scenario("UnknownPreset", "preset: mars\n", "mars");
  scenario("UnknownKey", Scenario("gravity: 9.8\n"), "gravity");
  scenario("FramesNegative", Scenario("frames: -1\n"), "frames");
  scenario("RateNaN", Scenario("rate_hz: .nan\n"), "rate_hz");
  scenario("RateZero", Scenario("rate_hz: 0\n"), "rate_hz");
  scenario("RateAboveAKilohertz", Scenario("rate_hz: 5000\n"), "rate_hz must be 0.01-1000 Hz");
  scenario("SeedHuge", Scenario("seed: 1e20\n"), "seed");
  scenario("TableHeightInfinite", Scenario("table_height_m: .inf\n"), "table_height_m");
  scenario("OccludedFramesNegative", Scenario("occluded_frames: -5\n"), "occluded_frames");
  scenario("UnknownMotionKind", Scenario("target_motion: {kind: teleport}\n"),
           "target_motion.kind");
  scenario("MotionSpeedNaN",
           Scenario("target_motion: {kind: linear, velocity_mps: [.nan, 0, 0]}\n"), "velocity");
  scenario("NoiseNegative", Scenario("noise: {sigma_scale: -1}\n"), "noise");
  scenario("ClutterUnknownKind", Scenario("clutter: [{kind: pyramid}]\n"), "kind must be box");
  scenario("ClutterBoxNegative",
           Scenario("clutter: [{kind: box, half_size_m: [-0.1, 0.1, 0.1], xz_m: [0, 1]}]\n"),
           "half_size_m");
  scenario("ClutterNotAList", Scenario("clutter: {kind: box}\n"), "clutter");
  scenario("NotYaml", "preset: [demo\n", "line");
  scenario("AMapForANumber", Scenario("frames: {a: 1}\n"), "frames");
  scenario("AListForANumber", Scenario("frames: [1, 2]\n"), "frames");
  scenario("PresetAMapping", "preset:\n p t:\n", "key 'preset': expected a scenario's name");
  scenario("AMapForAKey", Scenario("{frames: 1}: 2\n"), "a key is a list or a mapping");
  scenario("AListForAKeyInASection", Scenario("noise: {[a]: 1}\n"), "in 'noise'");
  // Issue 37: a key twice (the last would win), and numbers that are not finite, refused where
  // the file is read.
  scenario("KeyTwice", Scenario("frames: 3\nframes: 4\n"), "key 'frames' is given twice");
  scenario("KeyTwiceInASection", Scenario("noise:\n  enabled: true\n  enabled: false\n"),
           "key 'enabled' is given twice");
  scenario("StartNaN", Scenario("target_motion: {kind: linear, start_xz_m: [.nan, 1]}\n"),
           "key 'target_motion.start_xz_m': wrong type (expected a finite number)");
  scenario("YawInfinite", Scenario("target_motion: {yaw_rad: -.inf}\n"),
           "key 'target_motion.yaw_rad': wrong type (expected a finite number)");

  // Recognition configurations (--config).
  auto config = [&](const std::string& name, const std::string& yaml, const std::string& says) {
    add("Config" + name, {{"m.pcd", good}, {"c.yaml", yaml}},
        "recognize --model $D/m.pcd --scene $D/m.pcd --plain --config $D/c.yaml", 1, says);
  };
  config("UnknownKey", "recognition: {speed: 11}\n", "speed");
  config("UnknownSection", "detection: {}\n", "detection");
  config("MapForANumber", "recognition: {cluster_size: {a: 1}}\n", "cluster_size");
  config("ListForANumber", "recognition: {cluster_size: [1]}\n", "cluster_size");
  config("NegativeRadius", "recognition: {descriptor_radius: -0.02}\n", "descriptor_radius");
  config("NaNRadius", "recognition: {descriptor_radius: .nan}\n", "descriptor_radius");
  config("InfiniteThreshold", "recognition: {cluster_threshold: .inf}\n", "cluster_threshold");
  config("IntOverflow", "recognition: {max_support_half_window_px: 2147483648}\n",
         "max_support_half_window_px");
  config("IntAtTheEdge", "recognition: {max_support_half_window_px: 2147483647}\n",
         "max_support_half_window_px");
  config("WordForANumber", "fovea: {growth_factor: big}\n", "growth_factor");
  config("FoveaCentreOfTwo", "fovea: {center: [0, 1]}\n", "center");
  config("NotYaml", "recognition: {a: [}\n", "line");
  config("TabIndent", "recognition:\n\tcluster_size: 3\n", "line");
  config("AMapForAKey", "recognition: {{cluster_size: 3}: 4}\n", "in 'recognition'");
  config("SectionTwice", "recognition: {hough_threshold: 5}\nrecognition: {hough_threshold: 6}\n",
         "$D/c.yaml: line 2: key 'recognition' is given twice (first on line 1)");
  config("KeyTwiceInASection", "recognition:\n  hough_threshold: 5\n  hough_threshold: 6\n",
         "$D/c.yaml: line 3: key 'hough_threshold' is given twice (first on line 2)");
  config("ZeroQuaternion", "fovea: {outer_orientation: [0, 0, 0, 0]}\n",
         "key 'fovea.outer_orientation': wrong type (expected a rotation: [0, 0, 0, 0] turns "
         "nothing)");
  config("IsAFolder", "", "$D/c.yaml");
  c.back().files = {{"m.pcd", good}, {"c.yaml/", ""}};
  add("ConfigMissing", model_ok,
      "recognize --model $D/m.pcd --scene $D/m.pcd --plain --config $D/nothing.yaml", 1,
      "$D/nothing.yaml");

  // Evaluation configurations and cases.
  auto eval_configs = [&](const std::string& name, const std::string& yaml,
                          const std::string& says) {
    add("EvalConfigs" + name, {{"m.pcd", good}, {"c.yaml", yaml}},
        "eval --dataset $D/m.pcd --model $D/m.pcd --configs $D/c.yaml --out $D/out", 1, says);
  };
  eval_configs("UnknownPipeline", "configurations: [{name: a, pipeline: quantum}]\n",
               "configurations[0].pipeline");
  eval_configs("EntryNotAMap", "configurations: [3]\n", "configurations[0]");
  eval_configs("UnknownEntryKey", "configurations: [{name: a, colour: red}]\n", "colour");
  eval_configs("BadDefaults",
               "defaults: {recognition: {cluster_size: -1}}\nconfigurations: [{name: a}]\n",
               "cluster_size");
  eval_configs("ConfigurationsNotAList", "configurations: {name: a}\n", "configurations");
  eval_configs("AListForAKey", "configurations: [{[name]: a}]\n", "in 'configurations[0]'");
  auto cases = [&](const std::string& name, const std::string& yaml, const std::string& says) {
    add("Cases" + name, {{"m.pcd", good}, {"c.yaml", kConfigs}, {"k.yaml", yaml}},
        "eval --cases $D/k.yaml --data $D --configs $D/c.yaml --out $D/out", 1, says);
  };
  cases("NotAList", "cases: 3\n", "cases");
  cases("WithoutModel", "cases: [{name: a, scene: {file: m.pcd, object: 1}}]\n", "model");
  cases("ShortTruthPose",
        "cases: [{name: a, model: {file: m.pcd, object: 1}, scene: {file: m.pcd, object: 1}, "
        "truth_pose: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0]}]\n",
        "truth_pose");
  cases("ObjectNegative",
        "cases: [{name: a, model: {file: m.pcd, object: -1}, scene: {file: m.pcd, object: 1}}]\n",
        "object");
  cases("SceneMissing",
        "cases: [{name: a, model: {file: none.pcd, object: 1}, scene: {file: none.pcd, object: "
        "1}}]\n",
        "none.pcd");
  cases("UnknownKey",
        "cases: [{name: a, model: {file: m.pcd, object: 1}, scene: {file: m.pcd, object: 1}, "
        "weight: 2}]\n",
        "weight");
  // What the config fuzzer found: a flow mapping as a key (valid YAML) threw out of the loader.
  cases("AMapForAKey",
        "cases: [{name: a, model: {file: m.pcd, object: 1}, scene: {file: m.pcd, object: 1}, "
        "{category}: box}]\n",
        "in 'cases[0]'");

  // The daemon's configuration.
  auto daemon = [&](const std::string& name, const std::string& yaml, const std::string& says) {
    add("Saccaded" + name, {{"d.yaml", "model: synthetic:target\n" + yaml}},
        "saccaded --config $D/d.yaml", 2, says);
  };
  daemon("UnknownKey", "source: synthetic:static\nspeed: 3\n", "speed");
  add("SaccadedUnknownSource", {{"d.yaml", "model: synthetic:target\nsource: video:0\n"}},
      "saccaded --config $D/d.yaml", 1, "unknown kind 'video'");  // the source cannot open: 1
  daemon("StatusPeriodInfinite", "service: {status_period_s: .inf}\n", "status_period_s");
  daemon("ChannelPrefixTooLong", "lcm: {channel_prefix: " + std::string(60, 'A') + "}\n",
         "channel_prefix");
  daemon("ListForAString", "source: [a, b]\n", "source");
  daemon("AMapForAKey", "{source: a}: b\n", "a key is a list or a mapping");
  daemon("AListForAKeyInASection", "lcm: {[url]: x}\n", "in 'lcm'");
  daemon("NotYaml", "source: [a\n", "line");
  daemon("BomThenTab", kBom + "\tsource: x\n", "$D/d.yaml");
  return c;
}

// ---- the run ----------------------------------------------------------------------------

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

std::set<std::string> Tree(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    names.insert(fs::relative(e.path(), dir).string());
  return names;
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The case's name where gtest and ctest print the parameter.
void PrintTo(const BadInput& bad, std::ostream* os) { *os << bad.name; }

class BadInputs : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputs, OneLineTheRightExitCodeAndNothingWritten) {
  const BadInput& bad = GetParam();
  // One folder a process: the plain and the sanitized suites may run at once.
  const std::string root =
      ::testing::TempDir() + "saccade_bad_input_" + std::to_string(getpid()) + "/";
  const std::string dir = root + bad.name;
  const std::string run = root + bad.name + ".";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const File& f : bad.files) {
    if (!f.name.empty() && f.name.back() == '/') {
      fs::create_directories(dir + "/" + f.name);
    } else {
      std::ofstream(dir + "/" + f.name, std::ios::binary) << f.content;
    }
  }
  const std::set<std::string> before = Tree(dir);
  const bool daemon = bad.command.rfind("saccaded ", 0) == 0;
  const std::string binary = daemon ? SACCADED_BINARY : SACCADE_BINARY;
  const std::string args = Replace(daemon ? bad.command.substr(9) : bad.command, "$D", dir);
  // No LCM traffic leaves the machine: saccaded, should it start, publishes to a closed URL.
  const std::string cmd = "LCM_DEFAULT_URL=udpm://239.255.76.67:7699?ttl=0 " + binary + " " + args +
                          " >" + run + "out 2>" + run + "err </dev/null";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << cmd << ": killed by signal " << WTERMSIG(status);
  const std::string out = Slurp(run + "out"), err = Slurp(run + "err");
  EXPECT_EQ(WEXITSTATUS(status), bad.code) << cmd << "\n" << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << cmd << "\n" << err;
  ASSERT_FALSE(err.empty()) << cmd << ": said nothing";
  EXPECT_EQ(err.back(), '\n') << err;
  EXPECT_NE(err.find(Replace(bad.says, "$D", dir)), std::string::npos) << cmd << "\n" << err;
  EXPECT_EQ(out, "") << cmd;
  EXPECT_EQ(Tree(dir), before) << cmd << ": wrote into its folder";
  fs::remove_all(dir);
  fs::remove(run + "out");
  fs::remove(run + "err");
}

std::string CaseName(const ::testing::TestParamInfo<BadInput>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Corpus, BadInputs, ::testing::ValuesIn(Corpus()), CaseName);

TEST(BadInputCorpus, HoldsAtLeastAHundredAndTwentyCasesWithUniqueNames) {
  const auto corpus = Corpus();
  std::set<std::string> names;
  for (const auto& c : corpus) names.insert(c.name);
  EXPECT_EQ(names.size(), corpus.size());
  EXPECT_GE(corpus.size(), 120u);
}

}  // namespace
