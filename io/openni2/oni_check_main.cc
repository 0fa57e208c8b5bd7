// saccade-oni-check FILE.oni: plays a recording through libOpenNI2 to its end, in a process of
// its own. Debian's .oni driver (libOniFile) trusts what a file says: a crafted string length
// or property record, or a corrupt frame for its codecs, crashes it, and with it the program
// that opened the file. Saccade runs this first and opens a recording itself only when this
// played every frame of it (io/openni2_source.cc, CheckOniRecording).
//
// Exit 0: every depth frame was played. 1: libOpenNI2 refused the file (one line on stderr).
// Killed by a signal: libOpenNI2 crashed on it. The caller bounds the time it may take.
#include <OpenNI.h>

#include <cstdio>
#include <string>

#include <unistd.h>

namespace {

std::string Oneline(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  while (!text.empty() && text.front() == ' ') text.erase(0, 1);
  return text;
}

// Ends at once: an orderly shutdown races libOniFile's player thread (seen to crash).
[[noreturn]] void Refuse(const std::string& path, const std::string& what) {
  const std::string detail = Oneline(openni::OpenNI::getExtendedError());
  std::fprintf(stderr, "%s: %s%s%s\n", path.c_str(), what.c_str(), detail.empty() ? "" : ": ",
               detail.c_str());
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
  // Every record is decoded as the player reaches it, read or not: colour frames too once
  // their stream runs. As fast as it can, repeating (a wrap means the whole file was played).
  if (device.hasSensor(openni::SENSOR_COLOR) &&
      colour.create(device, openni::SENSOR_COLOR) == openni::STATUS_OK)
    colour.start();
  control->setSpeed(0.0f);
  control->setRepeatEnabled(true);
  if (depth.start() != openni::STATUS_OK) Refuse(path, "cannot start playback");
  int last = -1;
  for (;;) {
    openni::VideoStream* streams[] = {&depth};
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(streams, 1, &ready, 5000) != openni::STATUS_OK)
      Refuse(path, "no frame for 5 s");
    openni::VideoFrameRef frame;
    if (depth.readFrame(&frame) != openni::STATUS_OK) Refuse(path, "a frame cannot be read");
    const int index = frame.getFrameIndex();
    if (index >= frames || index < last) break;  // the last frame, or the player wrapped
    last = index;
  }
  std::fflush(stderr);
  _exit(0);
}
