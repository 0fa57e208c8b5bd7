// saccade-oni-check FILE.oni: plays a recording through libOpenNI2 to its end, in a process of
// its own. Debian's .oni driver (libOniFile) trusts what a file says: a crafted string length
// or property record, or a corrupt frame for its codecs, crashes it, and with it the program
// that opened the file. Saccade runs this first and opens a recording itself only when this
// played every frame of it (io/sources/openni2_recording.cc, CheckOniRecording).
//
// Exit 0: every depth frame was played. 1: libOpenNI2 refused the file (one line on stderr).
// Killed by a signal: libOpenNI2 crashed on it. The caller bounds the time it may take.
#include "core/fail.h"

#include <OpenNI.h>

#include <cstdio>
#include <string>

#include <unistd.h>

namespace {

// Ends at once: an orderly shutdown races libOniFile's player thread (seen to crash).
[[noreturn]] void Refuse(const std::string& path, const std::string& what) {
  const std::string detail = saccade::OneLine(openni::OpenNI::getExtendedError());
  std::fprintf(
      stderr, "%s\n",
      saccade::OneLine(path + ": " + what + (detail.empty() ? "" : ": " + detail)).c_str());
  std::fflush(stderr);
  _exit(1);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: saccade-oni-check FILE.oni\n");
    return 2;
  }
  const std::string path = argv[1];
  if (openni::OpenNI::initialize() != openni::STATUS_OK)
    Refuse(path, "libOpenNI2 did not initialize");
  openni::Device device;
  if (device.open(path.c_str()) != openni::STATUS_OK) Refuse(path, "cannot open");
  openni::PlaybackControl* control = device.getPlaybackControl();
  if (!control) Refuse(path, "not a recording");
  openni::VideoStream depth, colour;
  if (depth.create(device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
    Refuse(path, "no depth stream");
  const int frames = control->getNumberOfFrames(depth);
  if (frames <= 0) Refuse(path, "the recording has no depth frame");
  // Manual playback, as `?mode=step` plays (io/sources/openni2_recording.cc, PlaybackSource): each
  // wait makes the player read and decode the file's next frame, of either stream. Repeating, so
  // the whole file has been played once the depth frame numbers go back after `frames` reads.
  // The numbers are the file's own: a file whose numbers never go back is refused after twice
  // its frame count, not played for ever.
  if (device.hasSensor(openni::SENSOR_COLOR) &&
      colour.create(device, openni::SENSOR_COLOR) == openni::STATUS_OK &&
      colour.start() != openni::STATUS_OK)
    Refuse(path, "cannot start its colour stream");
  control->setSpeed(-1.0f);
  control->setRepeatEnabled(true);
  if (depth.start() != openni::STATUS_OK) Refuse(path, "cannot start playback");
  openni::VideoStream* streams[] = {&depth, &colour};
  const int count = colour.isValid() ? 2 : 1;
  long reads = 0;
  int last = -1;
  for (;;) {
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(streams, count, &ready, 5000) != openni::STATUS_OK)
      Refuse(path, "no frame for 5 s");
    openni::VideoFrameRef frame;
    if (streams[ready]->readFrame(&frame) != openni::STATUS_OK)
      Refuse(path, "a frame cannot be read");
    if (ready != 0) continue;
    const int index = frame.getFrameIndex();
    if (++reads > frames && index < last) break;  // the player went back to the start
    if (reads > 2L * frames + 10) Refuse(path, "its frame numbers never go back to the start");
    last = index;
  }
  std::fflush(stderr);
  _exit(0);
}
