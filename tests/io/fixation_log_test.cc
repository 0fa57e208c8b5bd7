// The fixation log reader: lcm-logger files checked header-first and read with every length
// checked against the file, and fixation_t messages checked before lcm-gen's decoder (which
// copies (size_t)-1 bytes for a string length of 0 or below).
#include "io/fixation_log.h"

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/fixation_t.hpp>

#include <unistd.h>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace saccade {
namespace {

std::vector<std::uint8_t> Encoded(const std::string& reason) {
  fixation_t m{};
  m.utime = 1000;
  m.seq = 7;
  m.frame = "camera";
  m.fovea[2] = 1.0;
  m.growth = 0.05;
  m.mode = fixation_t::TRACKING;
  m.mode_name = "TRACKING";
  m.target = 0;
  m.model = 0;
  m.num_targets = 1;
  m.reason = reason;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// Sets the big-endian int32 at `at`.
void Put32(std::vector<std::uint8_t>* bytes, std::size_t at, std::int32_t value) {
  const auto u = static_cast<std::uint32_t>(value);
  for (int b = 0; b < 4; ++b) (*bytes)[at + b] = static_cast<std::uint8_t>(u >> (24 - 8 * b));
}

TEST(DecodeFixation, AStringLengthOfZeroNegativeOrPastTheEndIsMalformedNotACrash) {
  const std::vector<std::uint8_t> good = Encoded("found");
  LoggedFixation f;
  ASSERT_TRUE(DecodeFixation(good.data(), good.size(), &f));
  EXPECT_EQ(f.frame, "camera");
  EXPECT_EQ(f.fixation.frame_seq, 7);
  // The first string (frame) starts after the hash, utime and seq: its length is at byte 24.
  for (std::int32_t length : {0, -1, -100, std::numeric_limits<std::int32_t>::min(), 1 << 30}) {
    std::vector<std::uint8_t> bad = good;
    Put32(&bad, 24, length);
    EXPECT_FALSE(DecodeFixation(bad.data(), bad.size(), &f)) << length;
  }
  // The last string (reason) cut short, and every shorter prefix of the message.
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_FALSE(DecodeFixation(good.data(), n, &f)) << n << " bytes";
}

TEST(ConvertFixationLog, CorruptStretchesAndATruncatedLastEventAreSkippedAndCounted) {
  const std::string path =
      ::testing::TempDir() + "saccade_fixations_" + std::to_string(getpid()) + ".lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    const std::vector<std::uint8_t> bytes = Encoded("found");
    lcm::LogEvent e{};
    e.channel = "SACCADE_FIXATION";
    e.datalen = static_cast<std::int32_t>(bytes.size());
    e.data = const_cast<std::uint8_t*>(bytes.data());
    for (int i = 0; i < 2; ++i) {
      e.eventnum = i;
      e.timestamp = 1000 * i;
      ASSERT_EQ(log.writeEvent(&e), 0);
    }
  }
  std::string whole;
  {
    std::ifstream in(path, std::ios::binary);
    whole.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string event = whole.substr(whole.size() / 2);  // the second event
  // Garbage, a good event, an event whose data length lies, a good one, one cut short.
  std::string lying = event;
  lying[24] = '\x7f';  // its data length's high byte: 2 GB
  std::ofstream(path, std::ios::binary | std::ios::app)
      << std::string("\x01\x02garbage\xed\xa1", 11) << event << lying << event
      << event.substr(0, event.size() - 5);
  std::ostringstream csv;
  FixationWriter writer(csv, FixationWriter::Format::kCsv);
  FixationLogStats stats;
  std::string error;
  ASSERT_TRUE(ConvertFixationLog(path, "SACCADE_FIXATION", &writer, &stats, &error)) << error;
  EXPECT_EQ(stats.written, 4);  // the two written, and the two good ones after the garbage
  EXPECT_EQ(stats.skipped, 3);  // the garbage, the lying event and the cut one
}

TEST(CheckLcmLog, WhatIsNotAnLcmLogIsOneLine) {
  const std::string dir = ::testing::TempDir() + "saccade_lcmlog_" + std::to_string(getpid()) + "/";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "saccade_empty.lcmlog");
  std::ofstream(dir + "saccade_text.lcmlog") << "time,x,y\n";
  std::string error;
  EXPECT_FALSE(CheckLcmLog(dir + "saccade_empty.lcmlog", &error));
  EXPECT_NE(error.find("empty file"), std::string::npos) << error;
  EXPECT_FALSE(CheckLcmLog(dir + "saccade_text.lcmlog", &error));
  EXPECT_NE(error.find("not an lcm-logger log"), std::string::npos) << error;
  EXPECT_FALSE(CheckLcmLog("/dev/zero", &error));
  EXPECT_EQ(error, "/dev/zero: not a regular file (a device or a pipe?), not an lcm-logger log");
  EXPECT_FALSE(CheckLcmLog(dir, &error));
  EXPECT_EQ(error, dir + ": is a directory, not an lcm-logger log");
}

}  // namespace
}  // namespace saccade
