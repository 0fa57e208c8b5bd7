// What OpenNI2's device and recording sources share (openni2_device.cc, openni2_recording.cc):
// libOpenNI2 brought up once, and StreamSource, the depth and colour streams with their pairing,
// recorder and callbacks (openni2_stream.cc). Internal to io/sources: include openni2_source.h.
#pragma once

#include "core/camera.h"
#include "core/registration.h"
#include "io/sources/frame_pairer.h"
#include "io/sources/openni2_source.h"

#include <OpenNI.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace saccade::openni2_internal {

using Clock = std::chrono::steady_clock;

/// libOpenNI2's last error in one line.
std::string LastOpenNIError();

/// Initializes libOpenNI2 once per process; it stays up (its drivers own threads that outlive
/// any one source).
bool InitializeOpenNI(std::string* error);

// How a depth frame becomes a cloud: the depth camera, and where colour comes from.
struct Conversion {
  CameraIntrinsics depth;        // the depth stream's camera
  bool register_colour = false;  // Saccade's registration: the depth moved into `colour`
  ColourCalibration calibration;
};

// What the device and playback sources share: the depth stream and the colour stream beside
// it, a recorder, the pairing of their frames, the mailbox that OpenNI2's callback threads fill,
// and the counters.
class StreamSource : public OpenNI2Source {
 public:
  explicit StreamSource(const ColourOptions& colour) : colour_options_(colour) {}
  // Each derived class stops and closes the streams in its own destructor, while OnFrame
  // still resolves to it; by the time this one runs the streams are closed.
  ~StreamSource() override = default;

  SourceStats Stats() const override;

  bool StartRecording(const std::string& path, std::string* error) override;

  // libOpenNI2 (2.2) can deadlock destroying a recorder while frames arrive: a stream's frame
  // thread, once past the recorder's started check, takes the stream's recorder lock and then
  // the recorder's stream lock (Recorder::record); destroy() takes them the other way round
  // (detachAllStreams). Seen as a hang of the .oni recording test on a loaded machine, every
  // thread waiting in libOpenNI2. After stop() no frame passes that check, so destroy() waits
  // until every stream being listened to has called back kCallbacksAfterStop more times. A
  // stream's frames come one at a time and wake its callback thread once recorded; the third
  // call after stop() was woken by a frame that came after stop(), so the one that may have
  // been past the check has left the locks. While callbacks come it waits on (a frame may be
  // held up behind the recorder's thread writing the file); once no stream has called back for
  // kDrainAtMost they have stalled, and it goes on (and after kDrainLongest in all whatever
  // comes: one stream may flow while the other has stalled). Going on unconfirmed is logged:
  // silence is not proof, a driver thread can be held in Recorder::record behind the
  // recorder's thread writing a frame, and then destroy() can still deadlock in libOpenNI2.
  // Not covered: stop() right after start(), before libOpenNI2's recorder thread has taken the
  // start (it sets started then, after this stop()); step-mode playback, whose frames are read,
  // not listened to (the player's frame in flight is not waited for).
  void StopRecording() override;

 protected:
  // Opens `uri`, its depth stream and, when asked and there, its colour stream with the
  // registration the options choose (`live`: a device, which may register; else a recording).
  bool OpenStream(const std::string& uri, bool live, std::string* error);

  bool StartStream(std::string* error);

  void CloseStream();

  // A new frame is ready on the depth stream (`depth`) or the colour stream; called from
  // OpenNI2's callback threads.
  virtual void OnFrame(bool depth) = 0;

  void RemoveListeners();

  // Where delivered frames go, one at a time and in order.
  using Sink = std::function<void(Item)>;

  // Reads the frame the depth (`depth`) or colour stream has ready and pairs it; what is ready
  // to deliver goes to `sink`. Returns false (with an error item to `sink`) when it cannot read.
  bool ReadAndPair(bool depth, const Sink& sink);

  // Delivers the depth frames still waiting for their colour, uncoloured (the stream ended).
  void FlushPending(const Sink& sink);
  bool HasPending() const;

  // One listener a stream: libOpenNI2 keeps one callback handle a listener, and hands it a
  // temporary VideoStream, so the listener itself says which stream it listens to.
  // Counts its calls for StopRecording.
  class Listener : public openni::VideoStream::NewFrameListener {
   public:
    Listener(StreamSource* owner, bool depth) : owner_(owner), depth_(depth) {}
    void onNewFrame(openni::VideoStream&) override {
      owner_->OnFrame(depth_);
      {
        std::lock_guard<std::mutex> lock(owner_->callback_mutex_);
        ++calls;
      }
      owner_->callback_.notify_all();
    }
    std::uint64_t calls = 0;  // guarded by the owner's callback_mutex_
    bool listening = false;   // likewise

   private:
    StreamSource* owner_;
    bool depth_;
  };

  void Listen(openni::VideoStream* stream, Listener* listener);

  static constexpr std::uint64_t kCallbacksAfterStop = 3;
  static constexpr std::chrono::milliseconds kDrainAtMost{1500};  // with no callback at all
  static constexpr std::chrono::seconds kDrainLongest{5};

  const ColourOptions colour_options_;
  Listener depth_listener_{this, true}, colour_listener_{this, false};
  openni::Device device_;
  openni::VideoStream depth_, colour_;
  openni::Recorder recorder_;
  std::mutex mutex_;           // the recorder
  std::mutex callback_mutex_;  // the listeners' counts, for StopRecording
  std::condition_variable callback_;
  std::atomic<std::uint64_t> skipped_{0};
  int last_index_ = 0;                // OpenNI2's own frame index of the last depth frame read
  bool stop_at_wrap_ = false;         // a playback that does not loop: set before streaming
  std::atomic<bool> wrapped_{false};  // such a playback met the recording's start again

 private:
  // A colour mode for a live device: RGB888 at the depth's size and rate when offered, else at
  // its size, else the largest. False when there is no RGB888 mode.
  bool ChooseRgbMode(const openni::VideoMode& depth);

  void ResetPairing();

  // A depth frame the pairer delivered, with its colour frame or none, and its number.
  struct Paired {
    openni::VideoFrameRef depth;
    std::optional<openni::VideoFrameRef> colour;
    std::uint64_t sequence;
  };

  // Converts what the pairer delivered and hands it to `sink` outside the pairing lock (the
  // other stream's thread pairs on meanwhile), in pairing order: the emit lock is taken before
  // the pairing lock is let go.
  void Emit(std::unique_lock<std::mutex>* lock, const Sink& sink);

  Conversion conversion_;
  mutable std::mutex pair_mutex_;  // the pairing state below, from either stream's thread
  std::mutex emit_mutex_;          // held while delivered frames are converted and handed on
  FramePairer<openni::VideoFrameRef, openni::VideoFrameRef> pairer_{
      16666, [this](const openni::VideoFrameRef& depth, const openni::VideoFrameRef* colour) {
        delivered_.push_back({depth,
                              colour ? std::optional<openni::VideoFrameRef>(*colour) : std::nullopt,
                              sequence_++});
      }};
  std::vector<Paired> delivered_;  // what the pairer delivered during the current call
  std::uint64_t sequence_ = 0;
};

}  // namespace saccade::openni2_internal
