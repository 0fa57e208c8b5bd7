// The fixation log reader: lcm-logger files checked header-first and read with every length
// checked against the file, and fixation_t messages checked before lcm-gen's decoder (which
// copies (size_t)-1 bytes for a string length of 0 or below).
#include "io/lcm/fixation_log.h"
#include "io/lcm/detections_log.h"

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>

#include <unistd.h>
#include <algorithm>
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
  m.sensor_utime = 900;
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
  // The first string (frame) starts after the hash, utime, sensor_utime and seq: its length is
  // at byte 32.
  for (std::int32_t length : {0, -1, -100, std::numeric_limits<std::int32_t>::min(), 1 << 30}) {
    std::vector<std::uint8_t> bad = good;
    Put32(&bad, 32, length);
    EXPECT_FALSE(DecodeFixation(bad.data(), bad.size(), &f)) << length;
  }
  // The last string (reason) cut short, and every shorter prefix of the message.
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_FALSE(DecodeFixation(good.data(), n, &f)) << n << " bytes";
}

TEST(FixationWriter, ColumnsNameTheirUnitsAndNumbersHaveTheirFloatPrecision) {
  const std::vector<std::uint8_t> bytes = Encoded("lost: track 0, then \"grow\"");
  LoggedFixation f;
  ASSERT_TRUE(DecodeFixation(bytes.data(), bytes.size(), &f));
  std::ostringstream csv, jsonl;
  FixationWriter(csv, TableFormat::kCsv).Write(f);
  FixationWriter(jsonl, TableFormat::kJsonl).Write(f);
  EXPECT_EQ(csv.str(),
            "utime_us,sensor_utime_us,seq,frame,fovea_x_m,fovea_y_m,fovea_z_m,velocity_x_mps,"
            "velocity_y_mps,velocity_z_mps,growth_m,mode,target,model,num_targets,reason\n"
            "1000,900,7,camera,0,0,1,0,0,0,0.05,TRACKING,0,0,1,\"lost: track 0, then "
            "\"\"grow\"\"\"\n");  // 0.05, not 0.0500000007; the comma and quotes quoted
  EXPECT_NE(jsonl.str().find("\"sensor_utime\":900"), std::string::npos) << jsonl.str();
  EXPECT_NE(jsonl.str().find("\"growth\":0.05,"), std::string::npos) << jsonl.str();
}

detections_t Detections(int instances) {
  detections_t m{};
  m.utime = 1700000000000000;
  m.sensor_utime = 33000;
  m.seq = 3;
  m.frame = "camera";
  m.foveated = true;
  m.fovea[2] = 0.8;
  m.growth = 0.1f;
  for (int k = 0; k < instances; ++k) {
    instance_t i{};
    i.utime = m.utime;
    i.model = k;
    i.model_name = "milk.pcd";
    i.centroid[0] = 0.2f, i.centroid[2] = 0.9f;
    i.quat[0] = 1;
    i.votes = 12;
    i.confidence = 0.75f;
    i.track_id = k;
    i.track_state = instance_t::TRACKING;
    i.track_state_name = "TRACKING";
    m.instances.push_back(i);
  }
  m.num_instances = instances;
  return m;
}

std::vector<std::uint8_t> Bytes(const detections_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

TEST(DecodeDetections, ALyingCountOrStringLengthIsMalformedNotACrash) {
  const std::vector<std::uint8_t> good = Bytes(Detections(2));
  LoggedDetections d;
  ASSERT_TRUE(DecodeDetections(good.data(), good.size(), &d));
  ASSERT_EQ(d.instances.size(), 2u);
  EXPECT_EQ(d.sensor_utime, 33000);
  EXPECT_EQ(d.instances[1].model_name, "milk.pcd");
  EXPECT_FLOAT_EQ(d.instances[1].centroid[2], 0.9f);
  // num_instances: after the hash, four int64, the frame string (4 + 7), foveated, fovea,
  // growth, fixation_seq and two floats.
  const std::size_t count_at = 8 + 32 + 11 + 1 + 24 + 8 + 8 + 8;
  for (std::int32_t count : {-1, 3, 1 << 20, std::numeric_limits<std::int32_t>::min()}) {
    std::vector<std::uint8_t> bad = good;
    Put32(&bad, count_at, count);
    EXPECT_FALSE(DecodeDetections(bad.data(), bad.size(), &d)) << count;
  }
  // The first instance's model_name length: after its utime and model.
  for (std::int32_t length : {0, -5, 1 << 30}) {
    std::vector<std::uint8_t> bad = good;
    Put32(&bad, count_at + 4 + 12, length);
    EXPECT_FALSE(DecodeDetections(bad.data(), bad.size(), &d)) << length;
  }
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_FALSE(DecodeDetections(good.data(), n, &d)) << n << " bytes";
}

TEST(DetectionWriter, OneCsvRowPerInstanceWithUnitsAndOneJsonLinePerFrame) {
  const std::vector<std::uint8_t> two = Bytes(Detections(2)), none = Bytes(Detections(0));
  LoggedDetections a, b;
  ASSERT_TRUE(DecodeDetections(two.data(), two.size(), &a));
  ASSERT_TRUE(DecodeDetections(none.data(), none.size(), &b));
  std::ostringstream csv, jsonl;
  DetectionWriter c(csv, TableFormat::kCsv), j(jsonl, TableFormat::kJsonl);
  for (const LoggedDetections* d : {&a, &b}) c.Write(*d), j.Write(*d);
  std::istringstream rows(csv.str());
  std::string header, row;
  std::getline(rows, header);
  EXPECT_EQ(header.rfind("utime_us,sensor_utime_us,seq,frame,model,model_name,track_id,"
                         "track_state,centroid_x_m,centroid_y_m,centroid_z_m,confidence,",
                         0),
            0u)
      << header;
  std::getline(rows, row);
  EXPECT_EQ(row.rfind("1700000000000000,33000,3,camera,0,milk.pcd,0,TRACKING,0.2,0,0.9,0.75,", 0),
            0u)
      << row;
  int n = 1;
  while (std::getline(rows, row)) ++n;
  EXPECT_EQ(n, 2);  // two instances; the empty frame writes no row
  const std::string lines = jsonl.str();
  EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 2);
  EXPECT_NE(lines.find("\"growth\":0.1,"), std::string::npos) << lines;
  EXPECT_NE(lines.find("\"instances\":[]"), std::string::npos) << lines;
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
  LcmLogStats stats;
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
