// Real programs under test: a private folder and multicast port, started children that are
// killed and reaped if a test fails early, files and lcm-logger logs read back, and polling for
// a condition with a generous deadline. Shared by the end-to-end tests (saccaded, the viewer).
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

extern char** environ;

namespace saccade::testing {

// A per-process folder and multicast port, so ctest -j runs do not hear each other.
struct Sandbox {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("saccade_test_" + std::to_string(getpid()));
  std::string url = "udpm://239.255.76.67:" + std::to_string(7700 + getpid() % 250) + "?ttl=0";
  Sandbox() { std::filesystem::create_directories(dir); }
  ~Sandbox() { std::filesystem::remove_all(dir); }
  std::string Path(const std::string& name) const { return (dir / name).string(); }
};

struct Exit {
  int code = -1;
  long max_rss_kb = 0;
};

// A started program. A test that fails before waiting for it must not leave it running (it
// would eat a core from every later test), so the destructor kills and reaps it.
class Child {
 public:
  explicit Child(pid_t pid) : pid_(pid) {}
  Child(Child&& other) noexcept : pid_(std::exchange(other.pid_, -1)) {}
  Child& operator=(Child&& other) noexcept {
    std::swap(pid_, other.pid_);
    return *this;
  }
  ~Child() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  void Signal(int signo) const { kill(pid_, signo); }
  pid_t Pid() const { return pid_; }
  Exit Wait() {
    int status = 0;
    rusage usage{};
    wait4(pid_, &status, 0, &usage);
    pid_ = -1;
    Exit e;
    e.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    e.max_rss_kb = usage.ru_maxrss;
    return e;
  }

 private:
  pid_t pid_;
};
inline Exit Wait(Child&& child) { return child.Wait(); }

// Starts a program with stdout and stderr to files.
inline Child Spawn(const std::vector<std::string>& argv, const std::string& out,
                   const std::string& err, const std::vector<std::string>& extra_env = {}) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> env_strings(extra_env);
  for (char** e = environ; *e; ++e) env_strings.push_back(*e);
  std::vector<char*> env;
  for (auto& e : env_strings) env.push_back(e.data());
  env.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  EXPECT_EQ(rc, 0) << "cannot start " << argv[0];
  return Child(rc == 0 ? pid : -1);
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// How many times `what` occurs in `text`.
inline int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size()))
    ++n;
  return n;
}

// Polls `done` until it holds or a generous deadline passes (a condition, not a timing).
inline bool WaitFor(const std::function<bool()>& done, double seconds = 120) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

struct LogEvents {
  std::vector<saccade::detections_t> detections;
  std::vector<saccade::fixation_t> fixations;
  std::vector<saccade::status_t> statuses;
  int probes = 0;
};

inline LogEvents ReadLog(const std::string& path) {
  LogEvents out;
  lcm::LogFile log(path, "r");
  if (!log.good()) return out;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel == "SACCADE_DETECTIONS") {
      saccade::detections_t m;
      if (m.decode(e->data, 0, e->datalen) >= 0) out.detections.push_back(m);
    } else if (e->channel == "SACCADE_FIXATION") {
      saccade::fixation_t m;
      if (m.decode(e->data, 0, e->datalen) >= 0) out.fixations.push_back(m);
    } else if (e->channel == "SACCADE_STATUS") {
      saccade::status_t m;
      if (m.decode(e->data, 0, e->datalen) >= 0) out.statuses.push_back(m);
    } else if (e->channel == "TEST_PROBE") {
      ++out.probes;
    }
  }
  return out;
}

// Debian's lcm-logger, started and known to be receiving before the test goes on: the test
// publishes probes until one shows up in the log.
class Logger {
 public:
  Logger(const Sandbox& box, const std::string& name) : path_(box.Path(name)) {
    child_ = Spawn({"lcm-logger", "-f", "--flush-interval=20", "--lcm-url=" + box.url, path_},
                   box.Path(name + ".out"), box.Path(name + ".err"));
    lcm::LCM lcm(box.url);
    EXPECT_TRUE(lcm.good());
    const char probe[] = "probe";
    EXPECT_TRUE(WaitFor([&] {
      lcm.publish("TEST_PROBE", probe, sizeof probe);
      return ReadLog(path_).probes > 0;
    })) << "lcm-logger never received anything on "
        << box.url << ": is there a multicast route (ip route add 224.0.0.0/4 dev lo)?";
  }
  // Stops the logger (it flushes on SIGINT) and reads what it wrote.
  LogEvents Finish() {
    child_.Signal(SIGINT);
    child_.Wait();
    return ReadLog(path_);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  Child child_{-1};
};

}  // namespace saccade::testing
