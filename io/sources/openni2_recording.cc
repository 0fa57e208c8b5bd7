// OpenNI2 recordings (.oni): checked in a process of their own, then played in realtime, fast
// or step mode.
#include "core/fail.h"
#include "io/base/log.h"
#include "io/base/text.h"
#include "io/sources/openni2_stream.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

extern char** environ;

namespace saccade {

namespace openni2_internal {
namespace {

// saccade-oni-check beside the running program (an installed layout), else the build's.
std::string OniCheckBinary() {
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    std::string dir(self, static_cast<std::size_t>(n));
    dir.erase(dir.rfind('/') + 1);
    if (access((dir + "saccade-oni-check").c_str(), X_OK) == 0) return dir + "saccade-oni-check";
  }
  return SACCADE_ONI_CHECK_BINARY;
}

// Plays the recording to its end in a child process (saccade-oni-check) before this process
// opens it: Debian's .oni driver crashes on crafted files (a string length or property record
// that lies, a corrupt frame), and a crash there must not take Saccade with it. The child has
// 30 s plus 1 s per 10 MB of file, in a process group of its own with no signal blocked (a
// daemon's signal thread blocks SIGTERM and the like, and a child inherits that); its stderr
// line is the reason when it refuses the file.
bool CheckOniRecording(const std::string& path, std::string* error) {
  std::uint64_t size = 0;
  if (!StatRegularFile(path, "a recording", &size, error)) return false;
  const std::string checker = OniCheckBinary();
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0)
    return Fail(error, path + ": cannot check the recording: " + std::strerror(errno));
  fcntl(out[0], F_SETFL, O_NONBLOCK);  // a grandchild keeping stderr open must not block us
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 2);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &all);
  posix_spawnattr_setpgroup(&attributes, 0);
  posix_spawnattr_setflags(&attributes,
                           POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  char* argv[] = {const_cast<char*>(checker.c_str()), const_cast<char*>(path.c_str()), nullptr};
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, checker.c_str(), &actions, &attributes, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(out[1]);
  if (rc != 0) {
    close(out[0]);
    return Fail(error,
                path + ": cannot check the recording (" + checker + "): " + std::strerror(rc));
  }
  // Its stderr, until the child has ended or the time is up (then its group is killed).
  const auto limit = std::chrono::seconds(30 + size / (10 << 20));
  const auto deadline = std::chrono::steady_clock::now() + limit;
  std::string said;
  const auto drain = [&] {
    char buffer[512];
    ssize_t got;
    while ((got = read(out[0], buffer, sizeof buffer)) > 0)
      if (said.size() < 4096) said.append(buffer, static_cast<std::size_t>(got));
    return got == 0;  // end of file
  };
  int status = 0;
  bool ended = false, closed = false;
  while (!ended) {
    const pid_t waited = waitpid(pid, &status, WNOHANG);
    if (waited == pid || (waited < 0 && errno != EINTR)) {
      ended = waited == pid;
      break;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{closed ? -1 : out[0], POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 100))) < 0 && errno != EINTR)
      break;
    if (p.revents != 0) closed = drain();
  }
  drain();
  close(out[0]);
  if (!ended) {
    kill(-pid, SIGKILL);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return Fail(error, path + ": libOpenNI2 did not finish playing it in " +
                           std::to_string(limit.count()) + " s; refused");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return true;
  // Refused: its one line, which names the file. Anything else is a crash: a signal, or (in a
  // sanitized build) the sanitizer that caught it ending the child with its report.
  said = said.substr(0, said.find('\n'));
  if (WIFEXITED(status) && WEXITSTATUS(status) == 1 && said.rfind(path + ": ", 0) == 0)
    return Fail(error, said);
  const std::string how = WIFSIGNALED(status) ? strsignal(WTERMSIG(status))
                                              : "exit " + std::to_string(WEXITSTATUS(status));
  return Fail(error, path + ": libOpenNI2 crashed playing it (" + how +
                         "): a corrupt or crafted recording; refused");
}

class PlaybackSource : public StreamSource {
 public:
  using StreamSource::StreamSource;
  bool Open(const std::string& path, const OniPlaybackOptions& options, std::string* error) {
    path_ = path;
    options_ = options;
    stop_at_wrap_ = !options.loop;
    if (!OpenStream(path, false, error)) return false;
    openni::PlaybackControl* control = device_.getPlaybackControl();
    if (!control) return Fail(error, path + ": not a recording");
    using Mode = OniPlaybackOptions::Mode;
    const float speed = options.mode == Mode::kRealtime ? 1.0f
                        : options.mode == Mode::kFast   ? 0.0f
                                                        : -1.0f;  // manual: one per read
    control->setSpeed(speed);
    // The end of a non-looping recording is detected here by counting frames. The player is
    // always left repeating: at the end of a file it otherwise spins over its stream list,
    // racing the destruction of the stream (Debian's libOniFile crashed so under load).
    control->setRepeatEnabled(true);
    frames_ = control->getNumberOfFrames(depth_);
    if (frames_ <= 0) return Fail(error, path + ": the recording has no depth frame");
    if (options.mode == Mode::kStep) {
      if (depth_.start() != openni::STATUS_OK ||
          (colour_.isValid() && colour_.start() != openni::STATUS_OK))
        return Fail(error, path + ": cannot start playback: " + LastOpenNIError());
      return true;
    }
    return StartStream(error);
  }

  ~PlaybackSource() override {
    Stop();
    StopRecording();  // while the listeners still count callbacks
    bool running = false;
    RemoveListeners();
    for (openni::VideoStream* stream : {&colour_, &depth_}) {
      if (!stream->isValid()) continue;
      stream->stop();
      running = true;
    }
    // libOniFile's player thread walks its stream list every 10 ms without a lock while no
    // stream runs; give it that beat to leave the walk before the streams are destroyed.
    if (running) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CloseStream();
  }

  Status Next(Frame* frame, std::string* error) override {
    if (options_.mode != OniPlaybackOptions::Mode::kStep) return StreamSource::Next(frame, error);
    // In manual playback the file driver reads the next frame of the file (of either stream)
    // when asked through waitForAnyStream (its manual trigger); a timeout keeps Stop()
    // responsive. After the last depth frame of a non-looping recording, a few more reads look
    // for its colour frame.
    int after_end = 0;
    const auto to_ready = [this](Item item) { ready_.push_back(std::move(item)); };
    while (ready_.empty()) {
      if (stopped_) return Status::kEnd;
      const bool at_end = !options_.loop && read_ >= frames_;
      if (at_end && (!HasPending() || after_end >= kReadsAfterEnd)) {
        FlushPending(to_ready);
        if (ready_.empty()) {
          SetState("ended");
          return Status::kEnd;
        }
        break;
      }
      openni::VideoStream* streams[] = {&depth_, &colour_};
      int ready = -1;
      const auto rc =
          openni::OpenNI::waitForAnyStream(streams, colour_.isValid() ? 2 : 1, &ready, 500);
      if (rc == openni::STATUS_TIME_OUT) continue;
      if (rc != openni::STATUS_OK) {
        Fail(error, path_ + ": playback failed: " + LastOpenNIError());
        return Status::kError;
      }
      if (at_end) {
        ++after_end;
        if (ready == 0) {  // the repeating player's next pass: not this playback's
          openni::VideoFrameRef skipped;
          depth_.readFrame(&skipped);
          continue;
        }
      } else if (ready == 0) {
        ++read_;
      }
      ReadAndPair(ready == 0, to_ready);
    }
    Item item = std::move(ready_.front());
    ready_.erase(ready_.begin());
    if (!item.ok) {
      Fail(error, path_ + ": " + item.error);
      return Status::kError;
    }
    *frame = std::move(item.frame);
    return Status::kFrame;
  }

  void OnFrame(bool depth) override {
    if (stopped_ || ended_) return;
    // The player repeats (see Open): a non-looping playback ends at the last frame, or at the
    // wrap when libOpenNI2 skipped the last frame in fast mode (ReadAndPair sees it and keeps
    // the next pass's first frame out).
    const auto put = [this](Item item) { mailbox_.Put(std::move(item)); };
    ReadAndPair(depth, put);
    if (depth && !options_.loop && (wrapped_ || last_index_ >= frames_)) {
      ended_ = true;
      FlushPending(put);
      SetState("ended");
      mailbox_.Close();
    }
  }
  bool Live() const override { return options_.mode != OniPlaybackOptions::Mode::kStep; }
  std::string Describe() const override {
    return path_ + " (" + std::to_string(frames_) + " frames" +
           (colour_.isValid() ? ", depth and colour)" : ")");
  }

 private:
  static constexpr int kReadsAfterEnd = 2;
  std::string path_;
  OniPlaybackOptions options_;
  int frames_ = 0;
  int read_ = 0;             // depth frames read in step mode
  std::vector<Item> ready_;  // step mode: frames paired and not yet returned
  std::atomic<bool> ended_{false};
};

}  // namespace
}  // namespace openni2_internal

std::unique_ptr<OpenNI2Source> OpenOniPlayback(const std::string& path,
                                               const OniPlaybackOptions& options,
                                               const ColourOptions& colour, std::string* error) {
  if (!openni2_internal::CheckOniRecording(path, error) ||
      !openni2_internal::InitializeOpenNI(error))
    return nullptr;
  auto source = std::make_unique<openni2_internal::PlaybackSource>(colour);
  if (!source->Open(path, options, error)) return nullptr;
  return source;
}

}  // namespace saccade
