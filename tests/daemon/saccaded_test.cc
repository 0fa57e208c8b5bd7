// saccaded end to end: the real binary, real LCM over UDP multicast on this host (ttl=0), and
// Debian's lcm-logger as the subscriber whose log the assertions read.
#include "core/sim/scenario.h"
#include "io/config/config.h"
#include "io/formats/cloud_io.h"
#include "io/lcm/command_key.h"
#include "support/processes.h"
#include "support/small_disk.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <net/if.h>
#include <net/route.h>
#include <netinet/in.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/ioctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/command_t.hpp>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <regex>
#include <sstream>
#include <thread>
#include <utility>

extern char** environ;

namespace saccade {
namespace {

namespace fs = std::filesystem;
const std::string kSaccaded = SACCADED_BINARY;
const std::string kSaccade = SACCADE_BINARY;
const std::string kSourceDir = SACCADE_SOURCE_DIR;

using namespace saccade::testing;  // Sandbox, Child, Spawn, Logger, ... (tests/support)

float TruthError(const saccade::instance_t& i, const Eigen::Isometry3f& X_CO) {
  Eigen::Isometry3f X_CM = Eigen::Isometry3f::Identity();
  X_CM.translate(Eigen::Vector3f(i.trans[0], i.trans[1], i.trans[2]));
  X_CM.rotate(Eigen::Quaternionf(i.quat[0], i.quat[1], i.quat[2], i.quat[3]).normalized());
  const Eigen::Vector3f c(i.centroid[0], i.centroid[1], i.centroid[2]);
  return (c - X_CO * (X_CM.inverse() * c)).norm();
}

TEST(Saccaded, TracksAMovingTargetThroughAnOcclusionOverRealLcm) {
  Sandbox box;
  Logger logger(box, "run.lcmlog");
  const std::string scenario_path = kSourceDir + "/configs/demo-scenario.yaml";
  const auto epoch_us = [] {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  };
  const std::int64_t started = epoch_us();
  Child daemon = Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                        "synthetic:" + scenario_path + "?rate=0", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  const Exit exit = daemon.Wait();
  const std::int64_t ended = epoch_us();
  ASSERT_EQ(exit.code, 0) << ReadFile(box.Path("err"));
  const LogEvents log = logger.Finish();
  // Its last line says how well it tracked against the scenario's truth, and what it dropped.
  const std::string err = ReadFile(box.Path("err"));
  std::smatch closing;
  ASSERT_TRUE(std::regex_search(err, closing,
                                std::regex("stopped: target within 2 cm in ([0-9]+) of ([0-9]+) "
                                           "frames it was visible in, median error ([0-9.]+) cm; "
                                           "0 of ([0-9]+) frames dropped at the source's rate\n$")))
      << err;
  EXPECT_GT(std::stoi(closing[2]), 0);
  EXPECT_GE(std::stoi(closing[1]), std::stoi(closing[2]) * 8 / 10);  // tracked in 80% or more
  EXPECT_LT(std::stod(closing[3]), 1.0);

  Scenario scenario;
  std::string error;
  ASSERT_TRUE(LoadScenario(scenario_path, &scenario, &error)) << error;
  const int n = scenario.frames;
  // Every processed frame: exactly one DETECTIONS and one FIXATION, in frame order.
  ASSERT_EQ(static_cast<int>(log.detections.size()), n);
  ASSERT_EQ(static_cast<int>(log.fixations.size()), n);
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(log.detections[i].seq, i);
    EXPECT_EQ(log.fixations[i].seq, i);
    EXPECT_EQ(log.detections[i].utime, log.fixations[i].utime);
    EXPECT_EQ(log.detections[i].sensor_utime, log.fixations[i].sensor_utime);
    // utime is the epoch time the frame reached the host; sensor_utime the scenario's clock.
    EXPECT_GE(log.detections[i].utime, started);
    EXPECT_LE(log.detections[i].utime, ended);
    if (i > 0) {
      EXPECT_GT(log.detections[i].sensor_utime, log.detections[i - 1].sensor_utime);
    }
  }
  ASSERT_FALSE(log.statuses.empty());
  EXPECT_EQ(log.statuses.back().frames_processed, n);
  EXPECT_EQ(log.statuses.back().frames_dropped, 0);

  // Found within 2 cm of the truth in at least 95% of the frames where it is visible.
  const int hidden_from = scenario.occluded_from;
  const int hidden_to = scenario.occluded_from + scenario.occluded_frames;  // exclusive
  int visible = 0, found = 0;
  std::string missed;
  for (int i = 0; i < n; ++i) {
    if (i >= hidden_from && i < hidden_to) continue;
    ++visible;
    const Eigen::Isometry3f X_CO = ScenarioTargetPose(scenario, i);
    float best = 1e9f;
    for (const auto& instance : log.detections[i].instances)
      best = std::min(best, TruthError(instance, X_CO));
    if (best < 0.02f)
      ++found;
    else
      missed += " " + std::to_string(i) + (best < 1e9f ? "(" + std::to_string(best) + " m)" : "");
  }
  EXPECT_GE(found, 0.95 * visible)
      << found << " of " << visible << " visible frames; missed:" << missed;

  // Hidden: searching, with G never shrinking.
  for (int i = hidden_from; i < hidden_to; ++i) {
    EXPECT_EQ(log.fixations[i].mode, int{saccade::fixation_t::SEARCHING}) << "frame " << i;
    if (i > hidden_from) {
      EXPECT_GE(log.fixations[i].growth, log.fixations[i - 1].growth);
    }
  }
  EXPECT_GT(log.fixations[hidden_to - 1].growth, log.fixations[hidden_from].growth);
  // Back in view: re-acquired within 5 frames, with G back to G_min (0 here).
  int reacquired = -1;
  for (int i = hidden_to; i < n && reacquired < 0; ++i)
    if (log.fixations[i].mode == saccade::fixation_t::TRACKING) reacquired = i;
  ASSERT_GE(reacquired, 0);
  EXPECT_LE(reacquired - hidden_to, 5);
  EXPECT_EQ(log.fixations[reacquired].growth, 0.0);

  // The user's converter reads the same log into one CSV row per fixation.
  const std::string csv = box.Path("fixations.csv");
  ASSERT_EQ(Wait(Spawn({kSaccade, "fixations", logger.path(), "--out", csv}, box.Path("cout"),
                       box.Path("cerr")))
                .code,
            0)
      << ReadFile(box.Path("cerr"));
  std::ifstream rows(csv);
  std::string line;
  int lines = 0;
  std::getline(rows, line);
  EXPECT_EQ(line.rfind("utime_us,sensor_utime_us,seq,", 0), 0u);
  while (std::getline(rows, line)) ++lines;
  EXPECT_EQ(lines, n);

  // And the detections: one CSV row per instance, one JSON line per frame.
  int instances = 0;
  for (const auto& d : log.detections) instances += d.num_instances;
  ASSERT_GT(instances, 0);
  for (const char* name : {"detections.csv", "detections.jsonl"}) {
    const std::string out = box.Path(name);
    ASSERT_EQ(Wait(Spawn({kSaccade, "detections", logger.path(), "--out", out}, box.Path("cout"),
                         box.Path("cerr")))
                  .code,
              0)
        << ReadFile(box.Path("cerr"));
    const std::string text = ReadFile(out);
    const bool csv_out = std::string(name).find(".csv") != std::string::npos;
    EXPECT_EQ(Count(text, "\n"), csv_out ? instances + 1 : n) << name;
    // The first frame with an instance leads: its epoch utime, then its sensor time.
    const auto first = std::find_if(log.detections.begin(), log.detections.end(),
                                    [](const auto& d) { return d.num_instances > 0; });
    const std::string stamp = (csv_out ? "" : "{\"utime\":") + std::to_string(first->utime) +
                              (csv_out ? "," : ",\"sensor_utime\":") +
                              std::to_string(first->sensor_utime);
    EXPECT_NE(text.find(stamp), std::string::npos) << stamp << "\n" << text.substr(0, 400);
  }
  // Messages of another type (or of an older saccaded's, another fingerprint): one line, exit
  // 1, and no file of a header alone.
  const std::string wrong = box.Path("wrong.csv");
  EXPECT_EQ(Wait(Spawn({kSaccade, "detections", logger.path(), "--channel", "SACCADE_FIXATION",
                        "--out", wrong},
                       box.Path("cout"), box.Path("cerr")))
                .code,
            1);
  EXPECT_NE(ReadFile(box.Path("cerr"))
                .find("none of the " + std::to_string(n) +
                      " message(s) on the channel decode as a detections_t"),
            std::string::npos)
      << ReadFile(box.Path("cerr"));
  EXPECT_FALSE(fs::exists(wrong));
}

// The daemon's own LCM client in the test: waits for a condition on the status channel.
class StatusWatch {
 public:
  explicit StatusWatch(const std::string& url) : lcm_(url) {
    lcm_.subscribe("SACCADE_STATUS", &StatusWatch::On, this);
    lcm_.subscribe("SACCADE_FIXATION", &StatusWatch::OnFixation, this);
  }
  bool WaitFor(const std::function<bool(const saccade::status_t&)>& done) {
    return saccade::WaitFor([&] {
      lcm_.handleTimeout(50);
      return have_ && done(last_);
    });
  }
  /// Waits for a fixation that satisfies `done` among those received since the last
  /// successful call (none is missed while waiting for something else).
  /// True once the daemon has processed ten frames more than when this is called.
  bool ProcessesTenMoreFrames() {
    std::int64_t before = 0;
    WaitFor([&](const saccade::status_t& s) { return (before = s.frames_processed) > 0; });
    return WaitFor([&](const saccade::status_t& s) { return s.frames_processed > before + 10; });
  }
  bool WaitForFixation(const std::function<bool(const saccade::fixation_t&)>& done) {
    return saccade::WaitFor([&] {
      lcm_.handleTimeout(50);
      for (; unchecked_ < fixations_.size(); ++unchecked_) {
        if (done(fixations_[unchecked_])) {
          ++unchecked_;
          return true;
        }
      }
      return false;
    });
  }
  lcm::LCM& lcm() { return lcm_; }

 private:
  void On(const lcm::ReceiveBuffer*, const std::string&, const saccade::status_t* m) {
    last_ = *m;
    have_ = true;
  }
  void OnFixation(const lcm::ReceiveBuffer*, const std::string&, const saccade::fixation_t* m) {
    fixations_.push_back(*m);
  }
  lcm::LCM lcm_;
  saccade::status_t last_;
  bool have_ = false;
  std::vector<saccade::fixation_t> fixations_;
  std::size_t unchecked_ = 0;
};

// systemd's end of sd_notify: a datagram socket drained by its own thread, as systemd reads
// its socket at once (a full socket would block the daemon's sd_notify).
class NotifySocket {
 public:
  explicit NotifySocket(const std::string& path) : path_(path) {
    fd_ = socket(AF_UNIX, SOCK_DGRAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
    EXPECT_EQ(bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    reader_ = std::thread([this] {
      char buffer[512];
      for (;;) {
        const ssize_t got = recv(fd_, buffer, sizeof buffer, 0);
        if (got <= 0) return;  // shut down
        std::lock_guard<std::mutex> lock(mutex_);
        messages_.emplace_back(buffer, static_cast<std::size_t>(got));
        arrived_.notify_all();
      }
    });
  }
  ~NotifySocket() {
    shutdown(fd_, SHUT_RDWR);
    reader_.join();
    close(fd_);
  }
  /// Waits for the next message that starts with `prefix` after those already waited for; a
  /// generous deadline for one that never comes (not a timing).
  bool WaitFor(const std::string& prefix) {
    std::unique_lock<std::mutex> lock(mutex_);
    return arrived_.wait_for(lock, std::chrono::seconds(60), [&] {
      for (; next_ < messages_.size(); ++next_)
        if (messages_[next_].rfind(prefix, 0) == 0) return ++next_, true;
      return false;
    });
  }
  /// Every message so far, each followed by ';'.
  std::string All() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string all;
    for (const std::string& m : messages_) all += m + ";";
    return all;
  }
  /// The last message that starts with `prefix`; empty when none.
  std::string Last(const std::string& prefix) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto m = messages_.rbegin(); m != messages_.rend(); ++m)
      if (m->rfind(prefix, 0) == 0) return *m;
    return "";
  }
  std::string Env() const { return "NOTIFY_SOCKET=" + path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<std::string> messages_;  // guarded by mutex_
  std::size_t next_ = 0;               // guarded by mutex_
  std::thread reader_;
};

TEST(Saccaded, RejectsMalformedCommandsCountsThemAndKeepsRunning) {
  Sandbox box;
  StatusWatch watch(box.url);
  // A live looping source that never ends by itself; systemd's notify socket is ours.
  NotifySocket systemd(box.Path("notify.sock"));
  Child daemon = Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                        "synthetic:static?rate=10&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"), {systemd.Env(), "WATCHDOG_USEC=1000000"});
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) { return s.frames_processed > 0; }));

  const char garbage[] = "not a command_t";
  watch.lcm().publish("SACCADE_COMMAND", garbage, sizeof garbage);
  saccade::command_t far;
  far.kind = saccade::command_t::SET_FOVEA;
  far.fovea[0] = 0, far.fovea[1] = 0, far.fovea[2] = 100;  // 100 m away: out of range
  watch.lcm().publish("SACCADE_COMMAND", &far);
  saccade::command_t unknown;
  unknown.kind = 42;
  watch.lcm().publish("SACCADE_COMMAND", &unknown);
  saccade::command_t missing;
  missing.kind = saccade::command_t::SWITCH_MODEL;
  missing.model = box.Path("no-such-model.pcd");
  watch.lcm().publish("SACCADE_COMMAND", &missing);
  saccade::command_t look;
  look.kind = saccade::command_t::SET_FOVEA;
  look.fovea[0] = 0.5, look.fovea[1] = 0.1, look.fovea[2] = 1.5;
  watch.lcm().publish("SACCADE_COMMAND", &look);

  EXPECT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.commands_rejected == 4 && s.commands_accepted == 1;
  })) << ReadFile(box.Path("err"));
  EXPECT_TRUE(watch.WaitForFixation([](const saccade::fixation_t& f) {
    return f.reason.rfind("command", 0) == 0 && std::abs(f.fovea[0] - 0.5) < 1e-6 &&
           std::abs(f.fovea[2] - 1.5) < 1e-6;
  }));

  // PAUSE: no frame goes through until RESUME.
  saccade::command_t pause;
  pause.kind = saccade::command_t::PAUSE;
  watch.lcm().publish("SACCADE_COMMAND", &pause);
  std::int64_t frozen = -1;
  EXPECT_TRUE(watch.WaitFor([&](const saccade::status_t& s) {
    if (!s.paused) return false;
    const bool same = s.frames_processed == frozen;  // two periods in a row without a frame
    frozen = s.frames_processed;
    return same;
  }));
  saccade::command_t resume;
  resume.kind = saccade::command_t::RESUME;
  watch.lcm().publish("SACCADE_COMMAND", &resume);
  EXPECT_TRUE(watch.WaitFor(
      [&](const saccade::status_t& s) { return !s.paused && s.frames_processed > frozen; }));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("command rejected on SACCADE_COMMAND: malformed"), std::string::npos) << err;
  EXPECT_NE(err.find("out of range"), std::string::npos) << err;
  EXPECT_NE(err.find("unknown kind 42"), std::string::npos) << err;
  EXPECT_NE(err.find("no-such-model.pcd"), std::string::npos) << err;

  const std::string states = systemd.All();
  EXPECT_NE(states.find("READY=1"), std::string::npos) << states;
  EXPECT_NE(states.find("STOPPING=1"), std::string::npos) << states;
  EXPECT_NE(states.find("WATCHDOG=1"), std::string::npos) << states << err;
}

TEST(Saccaded, TellsSystemdItsStateStatusAndWatchdogAndLogsWithJournalPriorities) {
  Sandbox box;
  NotifySocket systemd(box.Path("notify.sock"));
  // stderr's file exists first, so that its device and inode can name it as journald's stream.
  const std::string err_path = box.Path("err");
  std::ofstream(err_path).close();
  struct stat err_stat {};
  ASSERT_EQ(stat(err_path.c_str(), &err_stat), 0);
  const std::string journal =
      "JOURNAL_STREAM=" + std::to_string(err_stat.st_dev) + ":" + std::to_string(err_stat.st_ino);
  const std::vector<std::string> args = {kSaccaded,
                                         "--config",
                                         kSourceDir + "/configs/demo.yaml",
                                         "--source",
                                         "synthetic:static?rate=10&loop=1",
                                         "--lcm-url",
                                         box.url};
  // A 0.4 s watchdog: pinged every 0.2 s (half of it), as long as frames flow.
  Child daemon =
      Spawn(args, box.Path("out"), err_path, {systemd.Env(), "WATCHDOG_USEC=400000", journal});
  ASSERT_TRUE(systemd.WaitFor("READY=1")) << systemd.All();
  for (int ping = 0; ping < 3; ++ping) ASSERT_TRUE(systemd.WaitFor("WATCHDOG=1")) << systemd.All();
  ASSERT_TRUE(systemd.WaitFor("STATUS=")) << systemd.All();
  const std::string status = systemd.Last("STATUS=");
  EXPECT_TRUE(
      std::regex_search(status, std::regex("^STATUS=(searching|tracking|full scan), [0-9.]+ "
                                           "fps, [0-9]+ dropped, [0-9]+ skipped")))
      << status;
  daemon.Signal(SIGHUP);
  EXPECT_TRUE(systemd.WaitFor("RELOADING=1")) << systemd.All();
  EXPECT_TRUE(systemd.WaitFor("READY=1")) << systemd.All();
  daemon.Signal(SIGTERM);
  EXPECT_TRUE(systemd.WaitFor("STOPPING=1")) << systemd.All();
  EXPECT_EQ(daemon.Wait().code, 0);
  // Every line of the log carries its priority: info is 6, and the watchdog says its interval.
  const std::string err = ReadFile(err_path);
  std::istringstream lines(err);
  int n = 0;
  for (std::string line; std::getline(lines, line); ++n)
    EXPECT_TRUE(std::regex_search(line, std::regex("^<[3467]>saccaded: "))) << line;
  EXPECT_GT(n, 2) << err;
  EXPECT_NE(err.find("<6>saccaded: info: systemd watchdog: pinged every 0.2"), std::string::npos)
      << err;

  // $WATCHDOG_PID names another process (the service's main process, when saccaded is its
  // child): saccaded must not ping for it. Two statuses pass, no ping among them.
  NotifySocket other(box.Path("notify2.sock"));
  Child child = Spawn(args, box.Path("out2"), box.Path("err2"),
                      {other.Env(), "WATCHDOG_USEC=400000", "WATCHDOG_PID=1"});
  ASSERT_TRUE(other.WaitFor("READY=1")) << other.All();
  ASSERT_TRUE(other.WaitFor("STATUS=")) << other.All();
  ASSERT_TRUE(other.WaitFor("STATUS=")) << other.All();
  child.Signal(SIGTERM);
  EXPECT_EQ(child.Wait().code, 0);
  EXPECT_EQ(other.All().find("WATCHDOG=1"), std::string::npos) << other.All();
  // Without a journal stream, plain lines.
  EXPECT_EQ(ReadFile(box.Path("err2")).rfind("saccaded: ", 0), 0u);
}

TEST(Saccaded, ReloadsAGoodConfigOnSighupAndKeepsTheOldOneOnABadOne) {
  Sandbox box;
  StatusWatch watch(box.url);
  const std::string config = box.Path("saccaded.yaml");
  fs::copy_file(kSourceDir + "/configs/demo.yaml", config);
  std::ofstream(config, std::ios::app) << "pipeline:\n  frames_in_flight: 1\n";
  Child daemon = Spawn({kSaccaded, "--config", config, "--source",
                        "synthetic:static?rate=10&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  ASSERT_TRUE(watch.WaitForFixation(
      [](const saccade::fixation_t& f) { return f.mode == saccade::fixation_t::TRACKING; }));

  std::ofstream(config, std::ios::app) << "bogus_key: 1\n";
  daemon.Signal(SIGHUP);
  EXPECT_TRUE(WaitFor(
      [&] { return ReadFile(box.Path("err")).find("reload failed") != std::string::npos; }));
  EXPECT_NE(ReadFile(box.Path("err")).find("key 'bogus_key': unknown key"), std::string::npos);
  // The old configuration still tracks.
  EXPECT_TRUE(watch.WaitForFixation(
      [](const saccade::fixation_t& f) { return f.mode == saccade::fixation_t::TRACKING; }));

  // A good new config that no instance can pass: the target is lost from then on.
  fs::copy_file(kSourceDir + "/configs/demo.yaml", config, fs::copy_options::overwrite_existing);
  std::ofstream(config, std::ios::app) << "pipeline:\n  frames_in_flight: 1\n";
  std::string text = ReadFile(config);  // a key is given once: demo.yaml's are changed in place
  text.replace(text.find("growth_max_m: 1.0"), 17, "growth_max_m: 0.1");
  text.replace(text.find("hough_threshold: 15"), 19, "hough_threshold: 100000");
  text.replace(text.find("consensus_min_votes: 15"), 23, "consensus_min_votes: 100000");
  std::ofstream(config) << text;
  daemon.Signal(SIGHUP);
  EXPECT_TRUE(WaitFor(
      [&] { return ReadFile(box.Path("err")).find("info: reloaded") != std::string::npos; }));
  EXPECT_TRUE(watch.WaitForFixation(
      [](const saccade::fixation_t& f) { return f.mode == saccade::fixation_t::FULL_SCAN; }));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
}

// A model file removed before a reload (a package upgrade, a user tidying the models folder):
// the reload fails naming the file, the model already loaded goes on tracking, and once the
// file is back the next SIGHUP loads it.
TEST(Saccaded, AModelFileRemovedOrHalfWrittenAtAReloadKeepsTheLoadedModelTracking) {
  Sandbox box;
  StatusWatch watch(box.url);
  const std::string model = box.Path("target.pcd");
  std::string error;
  ASSERT_TRUE(saccade::SaveCloud(model, saccade::SyntheticTargetModel(1), &error)) << error;
  const std::string config = box.Path("saccaded.yaml");
  fs::copy_file(kSourceDir + "/configs/demo.yaml", config);
  // demo.yaml's service section already says `summary: line`; a key is given once.
  std::ofstream(config, std::ios::app) << "pipeline:\n  frames_in_flight: 1\n";
  Child daemon = Spawn({kSaccaded, "--config", config, "--model", model, "--source",
                        "synthetic:static?rate=10&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  ASSERT_TRUE(watch.WaitForFixation([](const saccade::fixation_t& f) {
    return f.mode == saccade::fixation_t::TRACKING;
  })) << ReadFile(box.Path("err"))
      << ReadFile(box.Path("out"));

  // The file goes, and the reload changes a recognition option: the models must be described
  // again, from their files.
  const std::string kept = box.Path("kept.pcd");
  fs::rename(model, kept);
  std::string text = ReadFile(config);
  text.replace(text.find("hough_threshold: 15"), 19, "hough_threshold: 16");
  std::ofstream(config) << text;
  daemon.Signal(SIGHUP);
  EXPECT_TRUE(WaitFor(
      [&] { return ReadFile(box.Path("err")).find("reload failed") != std::string::npos; }));
  EXPECT_NE(ReadFile(box.Path("err")).find(model), std::string::npos) << ReadFile(box.Path("err"));
  // The next 30 fixations (3 s at 10 Hz: most of them made after the failed reload, whatever
  // was queued before it) all track.
  int fixations = 0, tracking = 0;
  EXPECT_TRUE(watch.WaitForFixation([&](const saccade::fixation_t& f) {
    tracking += f.mode == saccade::fixation_t::TRACKING;
    return ++fixations == 30;
  }));
  EXPECT_EQ(tracking, 30);

  // The status line a second names the instance by its model's short name, track and state.
  EXPECT_NE(ReadFile(box.Path("out")).find("| target #0 TRACKING ("), std::string::npos)
      << ReadFile(box.Path("out"));

  // The file comes back half written (a copy caught midway): refused as such, still tracking.
  const std::string whole = ReadFile(kept);
  std::ofstream(model, std::ios::binary) << whole.substr(0, whole.size() / 2);
  const auto failures = [&] {
    const std::string err = ReadFile(box.Path("err"));
    int n = 0;
    for (std::size_t at = err.find("reload failed"); at != std::string::npos;
         at = err.find("reload failed", at + 1))
      ++n;
    return n;
  };
  daemon.Signal(SIGHUP);
  EXPECT_TRUE(WaitFor([&] { return failures() == 2; })) << ReadFile(box.Path("err"));
  fixations = 0, tracking = 0;
  EXPECT_TRUE(watch.WaitForFixation([&](const saccade::fixation_t& f) {
    tracking += f.mode == saccade::fixation_t::TRACKING;
    return ++fixations == 30;
  }));
  EXPECT_EQ(tracking, 30);

  fs::rename(kept, model);  // the whole file replaces the half one at once
  daemon.Signal(SIGHUP);
  EXPECT_TRUE(WaitFor(
      [&] { return ReadFile(box.Path("err")).find("info: reloaded") != std::string::npos; }));
  EXPECT_TRUE(watch.WaitForFixation(
      [](const saccade::fixation_t& f) { return f.mode == saccade::fixation_t::TRACKING; }));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
}

// A source whose frames change size from one to the next (a driver switching modes, a folder
// of mixed captures): 64x48, 320x240 and 160x120 organized frames, one after the other. Each is
// processed, none stops the daemon, and it loops over them until told to stop.
// The multicast route of this process's network namespace (224.0.0.0/4 through lo), which LCM
// needs to open and to send: added, and removed to make every send fail.
class MulticastRoute {
 public:
  MulticastRoute() : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {}
  ~MulticastRoute() { close(fd_); }
  /// Brings lo up with multicast; false with errno's text in `why` when refused.
  bool LoopbackUp(std::string* why) const {
    ifreq ifr{};
    std::strncpy(ifr.ifr_name, "lo", IFNAMSIZ - 1);
    if (ioctl(fd_, SIOCGIFFLAGS, &ifr) != 0) return Fail(why);
    ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP | IFF_MULTICAST);
    return ioctl(fd_, SIOCSIFFLAGS, &ifr) == 0 || Fail(why);
  }
  bool Add(std::string* why) { return Route(SIOCADDRT, why); }
  bool Remove(std::string* why) { return Route(SIOCDELRT, why); }

 private:
  static bool Fail(std::string* why) {
    *why = std::strerror(errno);
    return false;
  }
  bool Route(unsigned long request, std::string* why) {
    rtentry rt{};
    auto set = [](sockaddr* a, std::uint32_t address) {
      sockaddr_in in{};
      in.sin_family = AF_INET;
      in.sin_addr.s_addr = htonl(address);
      std::memcpy(a, &in, sizeof in);
    };
    set(&rt.rt_dst, 0xE0000000u);      // 224.0.0.0
    set(&rt.rt_genmask, 0xF0000000u);  // /4
    rt.rt_flags = RTF_UP;
    char lo[] = "lo";
    rt.rt_dev = lo;
    return ioctl(fd_, request, &rt) == 0 || Fail(why);
  }
  int fd_;
};

// LCM sends that fail: the test and the daemon run in a network namespace of their own, whose
// multicast route the test removes while the daemon publishes, then puts back. Every send
// fails meanwhile (ENETUNREACH); the daemon must go on, count the frames it could not send,
// and publish again once the route is back. Needs root (a new network namespace).
TEST(Saccaded, ANetworkThatRefusesToSendIsSurvivedCountedAndResumed) {
  // Back to the host's network at the end, whatever fails: later tests of this binary (run
  // outside ctest) need it.
  const int host = open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
  ASSERT_GE(host, 0) << std::strerror(errno);
  struct BackToHost {
    int fd;
    ~BackToHost() {
      setns(fd, CLONE_NEWNET);
      close(fd);
    }
  } back_to_host{host};
  if (unshare(CLONE_NEWNET) != 0)
    GTEST_SKIP() << "no network namespace of its own (needs root): " << std::strerror(errno);
  MulticastRoute route;
  std::string why;
  ASSERT_TRUE(route.LoopbackUp(&why)) << why;
  ASSERT_TRUE(route.Add(&why)) << why;
  Sandbox box;
  StatusWatch watch(box.url);
  Child daemon = Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                        "synthetic:static?rate=30&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  std::int64_t before = 0;
  ASSERT_TRUE(watch.WaitFor([&](const saccade::status_t& s) {
    before = s.frames_processed;
    return s.frames_processed >= 5 && s.frames_unsent == 0;
  })) << ReadFile(box.Path("err"));

  ASSERT_TRUE(route.Remove(&why)) << why;
  // The first frame not sent; every one after it fails too until the route is back.
  const std::regex unsent_line("frame ([0-9]+): LCM did not send it");
  std::smatch first_unsent;
  std::string err;
  ASSERT_TRUE(WaitFor([&] {
    err = ReadFile(box.Path("err"));
    return std::regex_search(err, first_unsent, unsent_line);
  })) << ReadFile(box.Path("err"));
  const std::int64_t first_unsent_seq = std::stoll(first_unsent[1].str());
  ASSERT_TRUE(route.Add(&why)) << why;

  // Back: statuses arrive again, count what was not sent, and frames went on being processed.
  saccade::status_t after;
  ASSERT_TRUE(watch.WaitFor([&](const saccade::status_t& s) {
    after = s;
    return s.frames_unsent > 0 && s.frames_processed > before + s.frames_unsent;
  })) << ReadFile(box.Path("err"));
  EXPECT_LE(after.frames_unsent, after.frames_processed);
  // A fixation after the first unsent frame was sent after the route came back.
  EXPECT_TRUE(watch.WaitForFixation(
      [&](const saccade::fixation_t& f) { return f.seq > first_unsent_seq; }));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
  err = ReadFile(box.Path("err"));
  EXPECT_TRUE(std::regex_search(err, std::regex("LCM did not send [1-9][0-9]* of the frames")))
      << err;                                                         // the run line counts them
  EXPECT_EQ(err.find("saccaded: error:"), std::string::npos) << err;  // no error line
}

// A folder whose frames change size from one to the next, with a corrupt file among them: the
// others are each processed, the corrupt one is skipped and counted, and the daemon goes on.
TEST(Saccaded, FramesThatChangeSizeAreEachProcessedAndACorruptOneIsSkipped) {
  Sandbox box;
  StatusWatch watch(box.url);
  const std::string frames = box.Path("frames");
  fs::create_directories(frames);
  auto wall = [](int width, int height) {  // a wall 1 m away, seen by a 525 px camera
    saccade::Cloud cloud(width, height);
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u) {
        saccade::PointT& p = cloud[static_cast<std::size_t>(v * width + u)];
        p.x = (u - width / 2) / 525.0f, p.y = (v - height / 2) / 525.0f, p.z = 1.0f;
      }
    return cloud;
  };
  std::string error;
  ASSERT_TRUE(saccade::SaveCloud(frames + "/1.pcd", wall(64, 48), &error)) << error;
  ASSERT_TRUE(saccade::SaveCloud(frames + "/2.pcd", wall(320, 240), &error)) << error;
  ASSERT_TRUE(saccade::SaveCloud(frames + "/3.pcd", wall(160, 120), &error)) << error;
  std::ofstream(frames + "/4.pcd") << "VERSION 0.7\nFIELDS x y z\n";  // a header cut short
  const std::string config = box.Path("saccaded.yaml");
  fs::copy_file(kSourceDir + "/configs/demo.yaml", config);
  Child daemon = Spawn({kSaccaded, "--config", config, "--source",
                        "pcd:" + frames + "?loop=1&rate=30", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.frames_processed >= 9 && s.frames_skipped >= 3;  // three passes
  })) << ReadFile(box.Path("err"));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_EQ(err.find("saccaded: error:"), std::string::npos) << err;  // no error line
  // Named once (the first pass), counted every time.
  EXPECT_EQ(Count(err, "skipping an unusable frame: " + frames + "/4.pcd"), 1) << err;
  EXPECT_NE(err.find("unusable frame(s) of the source skipped"), std::string::npos) << err;
}

// Signals from outside that once broke it: a SIGUSR2 ended its signal handling (SIGTERM was
// then ignored), and a closed pipe on stderr killed it with SIGPIPE.
TEST(Saccaded, StraySignalsAndAClosedStderrDoNotStopTheHandlingOfSigterm) {
  Sandbox box;
  StatusWatch watch(box.url);
  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  const std::string err_pipe = "/dev/fd/" + std::to_string(pipe_fds[1]);
  Child daemon = Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                        "synthetic:static?rate=10&loop=1", "--lcm-url", box.url},
                       box.Path("out"), err_pipe);
  close(pipe_fds[0]);  // nobody reads its stderr any more: the next line it logs meets EPIPE
  close(pipe_fds[1]);
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) { return s.frames_processed > 0; }));
  daemon.Signal(SIGUSR2);
  daemon.Signal(SIGHUP);  // a reload logs a line: on the closed pipe
  const std::int64_t seen = [&] {
    std::int64_t n = 0;
    watch.WaitFor([&](const saccade::status_t& s) { return (n = s.frames_processed) > 0; });
    return n;
  }();
  EXPECT_TRUE(
      watch.WaitFor([&](const saccade::status_t& s) { return s.frames_processed > seen + 5; }));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
}

// saccaded on configs/demo.yaml over a synthetic scene looping at 10 Hz, on the box's LCM; its
// stdout and stderr in the box's out and err.
Child DemoDaemon(const Sandbox& box) {
  return Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                "synthetic:static?rate=10&loop=1", "--lcm-url", box.url},
               box.Path("out"), box.Path("err"));
}

// Commands built to hurt: models that are devices, pipes, /proc entries or folders, lying
// string lengths (0, negative, INT32_MIN, past the end), and a flood. Each is rejected and
// counted, the log stays short (the first five a second are said), and the daemon still
// tracks and stops on SIGTERM.
TEST(Saccaded, HostileCommandsAreRejectedCountedAndSurvived) {
  Sandbox box;
  StatusWatch watch(box.url);
  Child daemon = DemoDaemon(box);
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) { return s.frames_processed > 0; }));
  int sent = 0;
  // Each burst is counted before the next is sent: a burst larger than the socket's buffer
  // could be lost on a loaded machine (UDP), and this counts what the daemon rejected.
  const auto all_counted = [&] {
    return watch.WaitFor([&](const saccade::status_t& s) {
      return s.commands_rejected == sent && s.commands_accepted == 0;
    });
  };
  const std::string fifo = box.Path("model.fifo");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& model : {std::string("/dev/zero"), std::string("/proc/self/mem"), fifo,
                                   box.Path(""), std::string("/etc/passwd")}) {
    saccade::command_t m;
    m.kind = saccade::command_t::SWITCH_MODEL;
    m.model = model;
    watch.lcm().publish("SACCADE_COMMAND", &m);
    ++sent;
  }
  EXPECT_TRUE(all_counted()) << ReadFile(box.Path("err"));
  saccade::command_t valid;
  valid.kind = saccade::command_t::SWITCH_MODEL;
  valid.model = "x";
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(valid.getEncodedSize()));
  valid.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  for (const std::uint32_t length : {0u, 0xffffffffu, 0x80000000u, 3u, 1000000u}) {
    std::vector<std::uint8_t> lie = bytes;
    for (int i = 0; i < 4; ++i) lie[49 + i] = static_cast<std::uint8_t>(length >> (24 - 8 * i));
    watch.lcm().publish("SACCADE_COMMAND", lie.data(), static_cast<unsigned>(lie.size()));
    ++sent;
  }
  EXPECT_TRUE(all_counted()) << ReadFile(box.Path("err"));
  const char flood[] = "garbage";
  for (int burst = 0; burst < 5; ++burst) {
    for (int i = 0; i < 10; ++i, ++sent)
      watch.lcm().publish("SACCADE_COMMAND", flood, sizeof flood);
    EXPECT_TRUE(all_counted()) << ReadFile(box.Path("err"));
  }
  EXPECT_TRUE(watch.ProcessesTenMoreFrames());  // still tracking
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("'/dev/zero' is not a regular file"), std::string::npos) << err;
  EXPECT_NE(err.find("'/etc/passwd' is not under a model folder"), std::string::npos) << err;
  EXPECT_LT(std::count(err.begin(), err.end(), '\n'), 60) << "the flood flooded the log";
}

// Signing on (a key made by saccade keygen): one signed SET_FOVEA is acted on; 500 replays of
// it and 500 unsigned PAUSEs are all refused and counted, none acted on (never paused); then
// saccade command signs a PAUSE with the key (acted on) and, without the key, sends an unsigned
// RESUME (refused: it stays paused).
TEST(Saccaded, WithAKeyOnlySignedCommandsAreActedOnAndReplaysAreRefused) {
  Sandbox box;
  StatusWatch watch(box.url);
  const std::string key_path = box.Path("command.key");
  ASSERT_EQ(Wait(Spawn({kSaccade, "keygen", "--out", key_path}, box.Path("keygen.out"),
                       box.Path("keygen.err")))
                .code,
            0)
      << ReadFile(box.Path("keygen.err"));
  std::string text = ReadFile(kSourceDir + "/configs/demo.yaml");
  const std::string open = "commands: open";
  ASSERT_NE(text.find(open), std::string::npos);
  text.replace(text.find(open), open.size(),
               "commands: signed\n  command_key: \"" + key_path + "\"");
  text.replace(text.find("summary: line"), 13, "summary: off\n  status_period_s: 0.2");
  std::ofstream(box.Path("signed.yaml")) << text;
  Child daemon = Spawn({kSaccaded, "--config", box.Path("signed.yaml"), "--source",
                        "synthetic:static?rate=10&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) { return s.frames_processed > 0; }))
      << ReadFile(box.Path("err"));

  saccade::Digest key{};
  std::string error;
  ASSERT_TRUE(saccade::ReadCommandKey(key_path, &key, &error)) << error;
  saccade::command_t look{};
  look.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                   std::chrono::system_clock::now().time_since_epoch())
                   .count();
  look.sequence = 1;
  look.kind = saccade::command_t::SET_FOVEA;
  look.fovea[0] = 0.5, look.fovea[1] = 0.1, look.fovea[2] = 1.5;
  look.model = "";
  std::vector<std::uint8_t> signed_look(static_cast<std::size_t>(look.getEncodedSize()));
  look.encode(signed_look.data(), 0, static_cast<int>(signed_look.size()));
  saccade::SignCommand(key, &signed_look);
  const auto send = [&](const std::vector<std::uint8_t>& bytes) {
    watch.lcm().publish("SACCADE_COMMAND", bytes.data(), static_cast<unsigned>(bytes.size()));
  };
  send(signed_look);
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.commands_accepted == 1 && s.commands_rejected == 0;
  })) << ReadFile(box.Path("err"));
  EXPECT_TRUE(watch.WaitForFixation([](const saccade::fixation_t& f) {
    return f.reason.rfind("command", 0) == 0 && std::abs(f.fovea[0] - 0.5) < 1e-6 &&
           std::abs(f.fovea[2] - 1.5) < 1e-6;
  }));

  saccade::command_t pause{};
  pause.utime = look.utime;
  pause.sequence = 2;
  pause.kind = saccade::command_t::PAUSE;
  pause.model = "";
  std::vector<std::uint8_t> unsigned_pause(static_cast<std::size_t>(pause.getEncodedSize()));
  pause.encode(unsigned_pause.data(), 0, static_cast<int>(unsigned_pause.size()));
  // In bursts of 20, each counted before the next (UDP may drop a burst beyond its buffer).
  std::int64_t sent = 0, counted = 0;
  bool ever_paused = false;
  for (int burst = 0; burst < 50; ++burst) {
    for (int i = 0; i < 10; ++i, sent += 2) {
      send(signed_look);
      send(unsigned_pause);
    }
    ASSERT_TRUE(watch.WaitFor([&](const saccade::status_t& s) {
      ever_paused = ever_paused || s.paused;
      counted = s.commands_rejected;
      return counted == sent;
    })) << "burst "
        << burst << ": " << counted << " of " << sent << " counted";
  }
  EXPECT_EQ(sent, 1000);
  EXPECT_TRUE(watch.WaitFor([&](const saccade::status_t& s) {
    ever_paused = ever_paused || s.paused;
    return s.commands_accepted == 1 && s.commands_rejected == 1000 && !s.paused;
  }));
  EXPECT_FALSE(ever_paused);

  // The command line: signed with --key it is acted on; unsigned (no key at hand) it is not.
  ASSERT_EQ(Wait(Spawn({kSaccade, "command", "pause", "--key", key_path, "--lcm-url", box.url},
                       box.Path("pause.out"), box.Path("pause.err")))
                .code,
            0)
      << ReadFile(box.Path("pause.err"));
  EXPECT_NE(ReadFile(box.Path("pause.out")).find("sent pause on SACCADE_COMMAND, signed"),
            std::string::npos);
  EXPECT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.paused && s.commands_accepted == 2 && s.commands_rejected == 1000;
  }));
  ASSERT_EQ(Wait(Spawn({kSaccade, "command", "resume", "--key", box.Path("none.key"), "--lcm-url",
                        box.url},
                       box.Path("resume.out"), box.Path("resume.err")))
                .code,
            1);  // an explicit key that is not there
  EXPECT_NE(ReadFile(box.Path("resume.err")).find("none.key"), std::string::npos);
  saccade::command_t resume = pause;
  resume.kind = saccade::command_t::RESUME;
  resume.sequence = 3;
  watch.lcm().publish("SACCADE_COMMAND", &resume);  // unsigned
  EXPECT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.paused && s.commands_accepted == 2 && s.commands_rejected == 1001;
  }));

  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("commands signed with " + key_path), std::string::npos) << err;
  EXPECT_NE(err.find("a replay (this signed command was acted on already)"), std::string::npos)
      << err;
  EXPECT_NE(err.find("unsigned (commands must be signed"), std::string::npos) << err;
  EXPECT_NE(err.find("; commands: 2 acted on, 1001 refused"), std::string::npos) << err;
  EXPECT_LT(std::count(err.begin(), err.end(), '\n'), 80) << "the refusals flooded the log";
}

// Sends a running daemon a SWITCH_MODEL whose model path is `bytes` long.
void SendSwitchWithAPathOf(StatusWatch& watch, std::size_t bytes) {
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) { return s.frames_processed > 0; }));
  saccade::command_t huge{};
  huge.kind = saccade::command_t::SWITCH_MODEL;
  huge.model = "/var/lib/saccade/models/" + std::string(bytes, 'a') + ".pcd";
  watch.lcm().publish("SACCADE_COMMAND", &huge);
}

// A SWITCH_MODEL whose model path is 60 KB long (the most one datagram carries): refused,
// counted and said in one short line; the daemon tracks on. (A 1 MB one travels in LCM's
// fragments, which the kernel drops beyond its receive buffer, net.core.rmem_max: it never
// reaches saccaded; docs/RELIABILITY.md.)
TEST(Saccaded, ASixtyKilobyteModelPathIsRefusedAndCounted) {
  Sandbox box;
  StatusWatch watch(box.url);
  Child daemon = DemoDaemon(box);
  SendSwitchWithAPathOf(watch, 60000);
  EXPECT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.commands_rejected == 1 && s.commands_accepted == 0;
  })) << ReadFile(box.Path("err"));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("command rejected on SACCADE_COMMAND: malformed message (601"),
            std::string::npos)
      << err.substr(0, 2000);
  std::istringstream lines(err);
  for (std::string line; std::getline(lines, line);) EXPECT_LE(line.size(), 500u);
}

// A 1 MB command goes out in 16 LCM fragments; beyond the socket's receive buffer
// (net.core.rmem_max, 208 KB by default) the kernel drops them and the command never reaches
// saccaded. Either way it is accounted for: refused when it arrives whole, else counted in
// STATUS as datagrams dropped by the kernel, with a warning saying a command may be among them.
TEST(Saccaded, AMegabyteCommandIsRefusedOrCountedAsDroppedByTheKernel) {
  Sandbox box;
  StatusWatch watch(box.url);
  Child daemon = DemoDaemon(box);
  SendSwitchWithAPathOf(watch, 1 << 20);
  saccade::status_t seen{};
  EXPECT_TRUE(watch.WaitFor([&](const saccade::status_t& s) {
    seen = s;
    return s.commands_rejected == 1 || s.lcm_datagrams_dropped > 0;
  })) << ReadFile(box.Path("err"));
  EXPECT_EQ(seen.commands_accepted, 0);
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
  const std::string err = ReadFile(box.Path("err"));
  if (seen.lcm_datagrams_dropped > 0) {
    EXPECT_NE(err.find("LCM: the kernel dropped "), std::string::npos) << err.substr(0, 2000);
    EXPECT_NE(err.find("LCM datagrams dropped by the kernel: "), std::string::npos);
  } else {
    EXPECT_NE(err.find("command rejected on SACCADE_COMMAND: malformed message"), std::string::npos)
        << err.substr(0, 2000);
  }
}

// demo.yaml with the source a camera (`spec`) waited for `wait_s` at start.
std::string LateCameraConfig(const Sandbox& box, double wait_s,
                             const std::string& spec = "openni2://") {
  std::string text = ReadFile(kSourceDir + "/configs/demo.yaml");
  const std::size_t at = text.find("source: ");
  text.replace(at, text.find('\n', at) - at,
               "source:\n  spec: \"" + spec + "\"\n  wait_at_start_s: " + std::to_string(wait_s));
  const std::string config = box.Path("late.yaml");
  std::ofstream(config) << text;
  return config;
}

// The virtual OpenNI2 camera (through the real libOpenNI2) serves a folder that is not there
// when saccaded starts: it waits, saying so in STATUS, and streams once the folder appears,
// 10 s after the start (found at the next back-off step: 0.5 s doubling to 8 s).
TEST(Saccaded, ACameraThatComesTenSecondsLateIsWaitedForThenStreams) {
  Sandbox box;
  StatusWatch watch(box.url);
  const std::string frames = box.Path("frames"), camera = box.Path("camera");
  ASSERT_EQ(Wait(Spawn({kSaccade, "record", "--source", "synthetic:static?frames=10", "--out",
                        frames, "--format", "depth"},
                       box.Path("rec.out"), box.Path("rec.err")))
                .code,
            0);
  Child daemon = Spawn({kSaccaded, "--config", LateCameraConfig(box, 120), "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"),
                       {"LD_LIBRARY_PATH=" + std::string(SACCADE_OPENNI2_RUNTIME),
                        "SACCADE_VIRTUAL_DEVICE=" + camera});
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.source_state.rfind("waiting for device", 0) == 0 && s.frames_processed == 0 &&
           s.uptime_s >= 10;
  })) << ReadFile(box.Path("err"));
  fs::rename(frames, camera);  // the camera is plugged in
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.source_state == "streaming" && s.frames_processed >= 5;
  })) << ReadFile(box.Path("err"));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
}

// A camera that never comes ends the wait with one line and exit code 1.
TEST(Saccaded, ACameraThatNeverComesEndsTheWaitWithOneLine) {
  Sandbox box;
  Child daemon = Spawn({kSaccaded, "--config", LateCameraConfig(box, 1), "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"),
                       {"LD_LIBRARY_PATH=" + std::string(SACCADE_OPENNI2_RUNTIME),
                        "SACCADE_VIRTUAL_DEVICE=" + box.Path("no-camera")});
  EXPECT_EQ(daemon.Wait().code, 1);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("openni2://"), std::string::npos) << err;
  EXPECT_NE(err.find("s for it)"), std::string::npos) << err;
}

// The same through the real libfreenect: no Kinect on this machine.
TEST(Saccaded, AKinectThatNeverComesEndsTheWaitWithOneLine) {
  Sandbox box;
  Child daemon =
      Spawn({kSaccaded, "--config", LateCameraConfig(box, 1, "freenect://"), "--lcm-url", box.url},
            box.Path("out"), box.Path("err"), {});
  EXPECT_EQ(daemon.Wait().code, 1);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("freenect://: "), std::string::npos) << err;
  EXPECT_NE(err.find("s for it)"), std::string::npos) << err;
}

TEST(Saccaded, AFastLiveSourceDropsFramesButNotMemory) {
  Sandbox box;
  Logger logger(box, "fast.lcmlog");
  StatusWatch watch(box.url);
  // Every frame searched whole (tracking off, G_max 0, full-scan fallback): far slower than
  // 200 Hz.
  const std::string config = box.Path("slow.yaml");
  fs::copy_file(kSourceDir + "/configs/demo.yaml", config);
  std::ofstream(config, std::ios::app) << "pipeline:\n  frames_in_flight: 2\n"
                                       << "tracking:\n  enabled: false\n";
  std::string text = ReadFile(config);
  text.replace(text.find("growth_max_m: 1.0"), 17, "growth_max_m: 0.0");
  std::ofstream(config) << text;
  const std::string frames = box.Path("frames");
  ASSERT_EQ(Wait(Spawn({kSaccade, "record", "--source", "synthetic:static?frames=3", "--out",
                        frames, "--format", "depth"},
                       box.Path("rec.out"), box.Path("rec.err")))
                .code,
            0);
  Child daemon = Spawn({kSaccaded, "--config", config, "--source",
                        "depth:" + frames + "?rate=200&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  ASSERT_TRUE(watch.WaitFor([](const saccade::status_t& s) {
    return s.frames_dropped >= 20 && s.frames_processed >= 5;
  })) << ReadFile(box.Path("err"));
  daemon.Signal(SIGTERM);
  const Exit exit = daemon.Wait();
  EXPECT_EQ(exit.code, 0) << ReadFile(box.Path("err"));
  // Bounded memory: a handful of 640x480 frames, not a queue of every dropped one.
  EXPECT_LT(exit.max_rss_kb, 1500 * 1024);
  const LogEvents log = logger.Finish();
  ASSERT_FALSE(log.statuses.empty());
  const auto& last = log.statuses.back();
  EXPECT_GT(last.frames_dropped, 0);
  // Everything taken was published, in order; each frame was foveated with the fixation of
  // one of the 2 (frames in flight) processed before it, however many were dropped between.
  EXPECT_EQ(static_cast<std::int64_t>(log.detections.size()), last.frames_processed);
  for (std::size_t i = 1; i < log.detections.size(); ++i) {
    const auto& d = log.detections;
    EXPECT_GT(d[i].seq, d[i - 1].seq);
    const std::int64_t f = d[i].fixation_seq;  // -1: the start's fixation, before any frame
    EXPECT_TRUE(f == d[i - 1].seq || (i >= 2 && f == d[i - 2].seq) || (i < 2 && f == -1))
        << "frame " << d[i].seq << " used the fixation of frame " << d[i].fixation_seq;
  }
  // Every frame made was processed or counted as dropped (one may still be in the making).
  EXPECT_LE(last.frames_in - last.frames_processed - last.frames_dropped, 1);
  EXPECT_GE(last.frames_in - last.frames_processed - last.frames_dropped, 0);
}

TEST(Saccaded, LogFixationsWritesWhatTheDaemonPublishesLive) {
  Sandbox box;
  const std::string out = box.Path("live.jsonl");
  Child logger =
      Spawn({kSaccade, "log-fixations", "--out", out, "--count", "5", "--lcm-url", box.url},
            box.Path("log.out"), box.Path("log.err"));
  // A source that loops: the logger gets its 5 whenever it is ready.
  Child daemon = DemoDaemon(box);
  EXPECT_EQ(logger.Wait().code, 0) << ReadFile(box.Path("log.err"));
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
  std::ifstream in(out);
  std::string line;
  int rows = 0;
  std::int64_t last_seq = -1;
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_EQ(line.front(), '{');
    EXPECT_NE(line.find("\"mode\":\""), std::string::npos) << line;
    const auto at = line.find("\"seq\":");
    ASSERT_NE(at, std::string::npos) << line;
    const std::int64_t seq = std::stoll(line.substr(at + 6));
    EXPECT_GT(seq, last_seq);
    last_seq = seq;
  }
  EXPECT_EQ(rows, 5);
  EXPECT_NE(ReadFile(box.Path("log.err")).find("5 fixation(s) written"), std::string::npos);
}

// A disk that fills while fixations are logged (a tmpfs with 4 KB left, as root): the logger
// ends with exit 1 and one line saying why and how many it kept; the file holds exactly those,
// each line whole; the daemon publishes on.
TEST(Saccaded, LogFixationsOnADiskThatFillsKeepsEveryWholeLineAndSaysWhy) {
  Sandbox box;
  const saccade::testing::SmallDisk small(box.Path("disk"), "64k");
  if (!small.mounted()) GTEST_SKIP() << "needs root to mount a small tmpfs";
  const std::string& disk = small.dir();
  small.Fill(4);
  StatusWatch watch(box.url);
  Child daemon = Spawn({kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
                        "synthetic:static?rate=30&loop=1", "--lcm-url", box.url},
                       box.Path("out"), box.Path("err"));
  const std::string out = disk + "/fixations.csv";
  Child logger = Spawn({kSaccade, "log-fixations", "--out", out, "--lcm-url", box.url},
                       box.Path("log.out"), box.Path("log.err"));
  EXPECT_EQ(logger.Wait().code, 1);
  const std::string said = ReadFile(box.Path("log.err"));
  EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
  EXPECT_NE(said.find(out + ": cannot write it (No space left on device); the "), std::string::npos)
      << said;
  const std::size_t at = said.find("; the ") + 6;
  const int kept = std::atoi(said.c_str() + at);
  EXPECT_GT(kept, 5) << said;
  const std::string text = ReadFile(out);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "a half line at the end";
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), kept + 1) << "the header and each kept";
  std::istringstream lines(text);
  std::string line, header;
  std::getline(lines, header);
  const auto fields = std::count(header.begin(), header.end(), ',');
  while (std::getline(lines, line)) EXPECT_EQ(std::count(line.begin(), line.end(), ','), fields);
  EXPECT_TRUE(watch.ProcessesTenMoreFrames());  // publishing on
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0);
}

struct BadConfig {
  std::string text;
  std::string expected;  // in the one error line
};

TEST(Saccaded, BadConfigFilesStopItWithFileKeyAndReason) {
  Sandbox box;
  const std::vector<BadConfig> cases = {
      {"model: synthetic:target\nbogus: 1\n", "key 'bogus': unknown key"},
      {"model: synthetic:target\nattention:\n  growth_stepp: 1\n", "key 'attention.growth_stepp'"},
      {"model: synthetic:target\nrecognition:\n  hough_threshold: many\n",
       "key 'recognition.hough_threshold': wrong type"},
      {"model: synthetic:target\nattention:\n  growth_step: -1\n", "growth_step must be > 0"},
      {"model: synthetic:target\nattention:\n  fallback: pray\n", "expected full_scan | saccade"},
      {"model: synthetic:target\npipeline:\n  frames_in_flight: 0\n",
       "pipeline: frames_in_flight must be in [1, 16]"},
      {"model: synthetic:target\nlcm:\n  channel_prefix: [a, b]\n",
       "key 'lcm.channel_prefix': wrong type"},
      {"model: synthetic:target\nrecognition: {hough_threshold: {a: 1}}\n",
       "key 'recognition.hough_threshold': wrong type"},
      // Each once crashed or hung the daemon (issue 21): SIGFPE, a sleep that outlasted SIGTERM,
      // a prefix LCM refused on every publish.
      {"model: synthetic:target\nrecognition:\n  max_support_half_window_px: 2147483647\n",
       "max_support_half_window_px must be from 0 to 1000"},
      {"model: synthetic:target\nservice:\n  status_period_s: .inf\n",
       "key 'service.status_period_s': wrong type (expected a finite number)"},
      {"model: synthetic:target\nservice:\n  status_period_s: 1e9\n",
       "status_period_s must be from 0.05 to 3600"},
      // A key given twice: refused, where the last one used to win (issue 37).
      {"model: synthetic:target\nservice:\n  summary: line\nservice:\n  summary: off\n",
       "line 4: key 'service' is given twice (first on line 2)"},
      {"model: synthetic:target\nlcm:\n  channel_prefix: " + std::string(60, 'A') + "\n",
       "channel_prefix must be 1 to 52 characters"},
      {"model: [\n", "line"},
      {"source: synthetic:static\n", "no model"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = box.Path("bad" + std::to_string(i) + ".yaml");
    std::ofstream(path) << cases[i].text;
    const Exit exit = Wait(Spawn({kSaccaded, "--config", path, "--lcm-url", "memq://"},
                                 box.Path("out"), box.Path("err")));
    const std::string err = ReadFile(box.Path("err"));
    EXPECT_EQ(exit.code, 2) << cases[i].text;
    EXPECT_NE(err.find(cases[i].expected), std::string::npos) << err;
    if (i + 1 < cases.size()) {  // the last case's error is about the flags, not the file
      EXPECT_NE(err.find(path), std::string::npos) << err;
    }
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
  // Config paths that are not files: a folder once aborted it, a device would never end.
  for (const std::string& path : {box.Path(""), std::string("/dev/zero")}) {
    const Exit exit = Wait(Spawn({kSaccaded, "--config", path, "--lcm-url", "memq://"},
                                 box.Path("out"), box.Path("err")));
    const std::string err = ReadFile(box.Path("err"));
    EXPECT_EQ(exit.code, 2) << path;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find(path + ": "), std::string::npos) << err;
  }
  // Runtime failures: the source and the model cannot be opened.
  Exit exit = Wait(Spawn({kSaccaded, "--model", "synthetic:target", "--source",
                          "pcd:" + box.Path("nothing-here"), "--lcm-url", "memq://"},
                         box.Path("out"), box.Path("err")));
  EXPECT_EQ(exit.code, 1);
  EXPECT_NE(ReadFile(box.Path("err")).find("nothing-here"), std::string::npos);
  exit = Wait(Spawn({kSaccaded, "--model", box.Path("missing.pcd"), "--lcm-url", "memq://"},
                    box.Path("out"), box.Path("err")));
  EXPECT_EQ(exit.code, 1);
  EXPECT_NE(ReadFile(box.Path("err")).find("missing.pcd"), std::string::npos);
}

}  // namespace
}  // namespace saccade
