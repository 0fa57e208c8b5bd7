// saccade view end to end: the real viewer and saccaded over real LCM (UDP multicast on this
// host), Debian's lcm-logger as the reference for what was published, and Debian's chromium,
// headless, as the browser whose screenshot is checked pixel by pixel.
#include "io/base/json.h"
#include "io/lcm/detections_log.h"
#include "io/lcm/lcm_log.h"
#include "io/viewer/viewer.h"
#include "support/processes.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <png.h>
#include <saccade/status_t.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

namespace saccade {
namespace {

using namespace saccade::testing;  // Sandbox, Child, Spawn, Logger, WaitFor, ReadFile
namespace fs = std::filesystem;
const std::string kSaccaded = SACCADED_BINARY;
const std::string kSaccade = SACCADE_BINARY;
const std::string kSourceDir = SACCADE_SOURCE_DIR;
const std::string kChromium = CHROMIUM_BINARY;

// `saccade view` on a free port of 127.0.0.1; its address from the line it prints.
class Viewer {
 public:
  Viewer(const Sandbox& box, const std::string& name, const std::string& lcm_url,
         const std::string& port = "0")
      : out_(box.Path(name + ".out")), err_(box.Path(name + ".err")) {
    child_ = Spawn({kSaccade, "view", "--lcm-url", lcm_url, "--port", port}, out_, err_);
    const std::regex line("open http://127\\.0\\.0\\.1:([0-9]+)/ ");
    EXPECT_TRUE(WaitFor(
        [&] {
          std::smatch m;
          const std::string out = ReadFile(out_);
          if (!std::regex_search(out, m, line)) return false;
          port_ = std::stoi(m[1]);
          return true;
        },
        60))
        << "saccade view never said where it listens: " << ReadFile(err_);
  }
  ~Viewer() {
    child_.Signal(SIGTERM);
    child_.Wait();
  }
  int port() const { return port_; }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/"; }
  // GET `path`; the body, or "" with anything but 200.
  std::string Get(const std::string& path) const {
    httplib::Client client("127.0.0.1", port_);
    const auto r = client.Get(path);
    return r && r->status == 200 ? r->body : "";
  }

 private:
  std::string out_, err_;
  Child child_{-1};
  int port_ = -1;
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* At(int x, int y) const {
    return &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
  }
};

Image ReadPng(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  Image out;
  if (!png_image_begin_read_from_file(&png, path.c_str())) return out;
  png.format = PNG_FORMAT_RGB;
  out.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, out.rgb.data(), 0, nullptr)) return {};
  out.width = static_cast<int>(png.width);
  out.height = static_cast<int>(png.height);
  return out;
}

// Headless chromium on `url` with the page's fixed layout at scale 1: a screenshot (`png`), or
// the DOM after the page's scripts ran (returned).
std::string Chromium(const Sandbox& box, const std::string& url, const std::string& png = "") {
  std::vector<std::string> argv = {
      kChromium, "--headless", "--no-sandbox", "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader", "--hide-scrollbars", "--force-device-scale-factor=1",
      "--window-size=1300,800", "--user-data-dir=" + box.Path("chromium-profile"),
      // Enough virtual time for the page to poll, fetch the preview and render several times.
      "--virtual-time-budget=6000"};
  argv.push_back(png.empty() ? "--dump-dom" : "--screenshot=" + png);
  argv.push_back(url);
  const Exit exit = Wait(Spawn(argv, box.Path("chromium.out"), box.Path("chromium.err")));
  EXPECT_EQ(exit.code, 0) << ReadFile(box.Path("chromium.err"));
  return ReadFile(box.Path("chromium.out"));
}

// The numbers after `"key":[` (a JSON array of numbers) in `json`, after `from`.
std::vector<double> Numbers(const std::string& json, const std::string& key, std::size_t from = 0) {
  std::vector<double> out;
  const std::size_t at = json.find("\"" + key + "\":[", from);
  if (at == std::string::npos) return out;
  std::istringstream in(json.substr(at + key.size() + 4));
  double v;
  char sep = ',';
  while (sep == ',' && in >> v) {
    out.push_back(v);
    in >> sep;
  }
  return out;
}

double Number(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find("\"" + key + "\":", from);
  return at == std::string::npos ? NAN : std::stod(json.substr(at + key.size() + 3));
}

bool Chromium_present() { return !kChromium.empty() && fs::exists(kChromium); }

TEST(View, ShowsTheLiveDemoInARealBrowserWithTheDetectionWhereTheTruthProjects) {
  if (!Chromium_present())
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  Sandbox box;
  Logger logger(box, "run.lcmlog");
  Viewer view(box, "view", box.url);
  // The demo at the sensor's rate, with its preview on (configs/demo.yaml).
  const Exit daemon =
      Wait(Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                  "synthetic:" + kSourceDir + "/configs/demo-scenario.yaml", "--lcm-url", box.url},
                 box.Path("saccaded.out"), box.Path("saccaded.err")));
  ASSERT_EQ(daemon.code, 0) << ReadFile(box.Path("saccaded.err"));
  logger.Finish();

  // What lcm-logger heard last on DETECTIONS.
  std::vector<LoggedDetections> logged;
  LcmLogStats stats;
  std::string error;
  ASSERT_TRUE(ReadLcmLog(
      logger.path(), "SACCADE_DETECTIONS",
      [&](const unsigned char* data, std::size_t size) {
        logged.emplace_back();
        return DecodeDetections(data, size, &logged.back());
      },
      &stats, &error))
      << error;
  ASSERT_EQ(stats.skipped, 0);
  ASSERT_FALSE(logged.empty());
  const LoggedDetections& last = logged.back();
  ASSERT_FALSE(last.instances.empty()) << "the demo ends with its target in view";

  // /api/state carries the last DETECTIONS message's instances exactly.
  const std::string seq = "\"seq\":" + std::to_string(last.seq) + ",";
  std::string state;
  ASSERT_TRUE(WaitFor([&] {
    state = view.Get("/api/state");
    const std::size_t d = state.find("\"detections\":{");
    // and a status decoded whole (its layout checked field by field, status_t as it is now)
    return d != std::string::npos && state.find(seq, d) < state.find("\"instances\"", d) &&
           state.find("\"lcm_datagrams_dropped\":") != std::string::npos;
  })) << state;
  JsonWriter instances;
  WriteInstancesJson(last.instances, &instances);
  EXPECT_NE(state.find("\"instances\":" + instances.str() + ","), std::string::npos)
      << state << "\nexpected instances " << instances.str();
  EXPECT_NE(state.find("\"fixation\":{"), std::string::npos);
  EXPECT_NE(state.find("\"status\":{"), std::string::npos);
  EXPECT_NE(state.find("\"rejected\":0,"), std::string::npos);

  // The newest preview: its image and points are served, and it has the truth and an instance.
  const std::size_t p = state.find("\"preview\":{");
  ASSERT_NE(p, std::string::npos) << state;
  const auto preview_seq = static_cast<long long>(Number(state, "seq", p));
  EXPECT_FALSE(view.Get("/api/preview.jpg?seq=" + std::to_string(preview_seq)).empty());
  EXPECT_EQ(view.Get("/api/points.bin?seq=" + std::to_string(preview_seq)).size(),
            static_cast<std::size_t>(Number(state, "num_points", p)) * 7);
  const double width = Number(state, "width", p), height = Number(state, "height", p),
               fx = Number(state, "fx", p), fy = Number(state, "fy", p),
               cx = Number(state, "cx", p), cy = Number(state, "cy", p);
  const std::vector<double> truth = Numbers(state, "truth", p);
  ASSERT_EQ(truth.size(), 3u) << state;
  ASSERT_EQ(Numbers(state, "centroid", state.find("\"instances\":[", p)).size(), 3u)
      << "the last preview shows an instance: " << state.substr(p);
  // Where the truth lands on the page: the camera view is the page's top-left 640 x 480, the
  // preview stretched over it, its pixel centres at (u + 0.5) * scale on each axis.
  const double truth_x = (fx * truth[0] / truth[2] + cx + 0.5) * 640.0 / width;
  const double truth_y = (fy * truth[1] / truth[2] + cy + 0.5) * 480.0 / height;

  const std::string png = box.Path("page.png");
  Chromium(box, view.url(), png);
  const Image page = ReadPng(png);
  ASSERT_EQ(page.width, 1300) << png;
  ASSERT_EQ(page.height, 800);
  // The instance's marker is the only magenta on the camera view: its pixels centre on the
  // detection, which must be where the truth projects.
  double sx = 0, sy = 0;
  int marker = 0, dark = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      const std::uint8_t* c = page.At(x, y);
      if (c[0] > 220 && c[1] < 60 && c[2] > 220) sx += x, sy += y, ++marker;
      if (c[0] < 16 && c[1] < 16 && c[2] < 16) ++dark;
    }
  ASSERT_GT(marker, 40) << "no detection marker drawn (" << png << ")";
  EXPECT_NEAR(sx / marker, truth_x, 4.0) << png;
  EXPECT_NEAR(sy / marker, truth_y, 4.0) << png;
  EXPECT_LT(dark, 640 * 480 / 4) << "the camera image was not drawn (" << png << ")";
  // The 3D view (x from 648) rendered the cloud: many pixels off its clear colour, in many
  // shades (the levels' greys, the instance's colour, the boxes).
  int drawn = 0;
  std::set<int> shades;
  for (int y = 0; y < 480; ++y)
    for (int x = 648; x < 1288; ++x) {
      const std::uint8_t* c = page.At(x, y);
      if (std::abs(c[0] - 0x0b) + std::abs(c[1] - 0x0c) + std::abs(c[2] - 0x0e) > 30) {
        ++drawn;
        shades.insert((c[0] >> 4) << 8 | (c[1] >> 4) << 4 | (c[2] >> 4));
      }
    }
  EXPECT_GT(drawn, 3000) << "the 3D view is blank (" << png << ")";
  EXPECT_GT(shades.size(), 10u) << png;
}

TEST(View, SaysOnThePageWhenNoDaemonIsHeardAndRefusesABusyPort) {
  if (!Chromium_present())
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it)";
  Sandbox box;  // nothing publishes on its multicast port
  Viewer view(box, "view", box.url);
  const std::string state = view.Get("/api/state");
  EXPECT_NE(state.find("\"connected\":false"), std::string::npos) << state;
  EXPECT_NE(state.find("\"preview\":null"), std::string::npos) << state;
  EXPECT_TRUE(view.Get("/api/preview.jpg").empty());
  const std::string dom = Chromium(box, view.url());
  EXPECT_NE(dom.find("No saccaded heard on " + box.url), std::string::npos) << dom;

  // A second viewer on the same port: one line saying so, exit 1 (`timeout` ends it, and the
  // test fails, should it listen instead).
  const Exit busy = Wait(Spawn({"timeout", "60", kSaccade, "view", "--lcm-url", box.url, "--port",
                                std::to_string(view.port())},
                               box.Path("busy.out"), box.Path("busy.err")));
  EXPECT_EQ(busy.code, 1);
  const std::string err = ReadFile(box.Path("busy.err"));
  EXPECT_EQ(Count(err, "\n"), 1) << err;
  EXPECT_NE(err.find("cannot listen on 127.0.0.1:" + std::to_string(view.port())),
            std::string::npos)
      << err;
}

// A flood of statuses within the strips' minute (the fuzzer gives every message the same
// time) keeps at most the viewer's cap of samples a strip, not one a message.
TEST(View, AFloodOfStatusesKeepsTheStripsBounded) {
  ViewerState viewer{ViewerOptions{}};
  saccade::status_t m{};
  m.source = "synthetic:static";
  m.source_state = "streaming";
  m.fps = 30;
  m.num_stages = 0;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  ASSERT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  for (int i = 0; i < 10000; ++i)
    ASSERT_TRUE(viewer.OnMessage("SACCADE_STATUS", bytes.data(), bytes.size(), 1.0));
  const std::string json = viewer.StateJson(1.0);
  const std::size_t begin = json.find("\"fps\":[[");
  ASSERT_NE(begin, std::string::npos) << json.substr(0, 400);
  const std::size_t end = json.find("]]", begin);
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(std::count(json.begin() + static_cast<long>(begin),
                       json.begin() + static_cast<long>(end), '[') -
                1,
            4096);
}

}  // namespace
}  // namespace saccade
