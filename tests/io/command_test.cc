// The command decoder and the model-path policy, without a daemon: every malformed message of a
// corpus is refused with one line, well-formed ones decode to what was sent.
#include "io/base/log.h"
#include "io/lcm/bus.h"

#include <saccade/command_t.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <sys/stat.h>
#include <unistd.h>

namespace saccade {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> Encode(const saccade::command_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

saccade::command_t Switch(const std::string& model) {
  saccade::command_t m;
  m.kind = saccade::command_t::SWITCH_MODEL;
  m.model = model;
  return m;
}

std::optional<Command> Decode(const std::vector<std::uint8_t>& bytes, std::string* why) {
  return DecodeCommand(bytes.data(), bytes.size(), BusOptions{}, Eigen::Isometry3f::Identity(),
                       why);
}

TEST(DecodeCommand, WellFormedCommandsDecodeToWhatWasSent) {
  std::string why;
  auto c = Decode(Encode(Switch("/models/mug.pcd")), &why);
  ASSERT_TRUE(c) << why;
  EXPECT_EQ(c->kind, Command::Kind::kSwitchModel);
  EXPECT_EQ(c->model, "/models/mug.pcd");
  saccade::command_t look;
  look.kind = saccade::command_t::SET_FOVEA;
  look.fovea[0] = 0.5, look.fovea[1] = -0.1, look.fovea[2] = 1.5;
  c = Decode(Encode(look), &why);
  ASSERT_TRUE(c) << why;
  EXPECT_TRUE(c->fovea_m.isApprox(Eigen::Vector3f(0.5f, -0.1f, 1.5f)));
  for (const std::int8_t kind :
       {saccade::command_t::RESET, saccade::command_t::PAUSE, saccade::command_t::RESUME}) {
    saccade::command_t m;
    m.kind = kind;
    EXPECT_TRUE(Decode(Encode(m), &why)) << why;
  }
}

TEST(DecodeCommand, EveryMalformedMessageIsRefusedWithOneLine) {
  const std::vector<std::uint8_t> good = Encode(Switch("/models/mug.pcd"));
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> corpus;
  corpus.push_back({"empty", {}});
  corpus.push_back({"one byte", {0x42}});
  for (std::size_t cut : {8u, 16u, 24u, 48u, 49u, 53u, 58u})
    corpus.push_back({"cut at " + std::to_string(cut), {good.begin(), good.begin() + cut}});
  corpus.push_back({"one byte more", good});
  corpus.back().second.push_back(0);
  for (const std::uint32_t length :
       {0u, 1u, 2u, 0xffffffffu, 0x80000000u, 0x7fffffffu, 4097u, 100000u}) {
    std::vector<std::uint8_t> lie = good;
    for (int i = 0; i < 4; ++i) lie[49 + i] = static_cast<std::uint8_t>(length >> (24 - 8 * i));
    corpus.push_back({"model length " + std::to_string(length), lie});
  }
  std::vector<std::uint8_t> no_nul = good;
  no_nul[no_nul.size() - 33] = 'x';  // the string's NUL, before the 32-byte signature
  corpus.push_back({"no NUL", no_nul});
  std::vector<std::uint8_t> wrong_hash = good;
  wrong_hash[0] ^= 0xff;
  corpus.push_back({"wrong hash", wrong_hash});
  std::vector<std::uint8_t> unknown = Encode(Switch("x"));
  unknown[24] = 42;  // the kind byte
  corpus.push_back({"kind 42", unknown});
  corpus.push_back({"switch to nothing", Encode(Switch(""))});
  for (const double bad : {double(NAN), double(INFINITY), -double(INFINITY), 1e39, 11.0}) {
    saccade::command_t m;
    m.kind = saccade::command_t::SET_FOVEA;
    m.fovea[2] = bad;
    corpus.push_back({"fovea z " + std::to_string(bad), Encode(m)});
  }
  corpus.push_back({"a huge model name", Encode(Switch(std::string(5000, 'a')))});
  for (const auto& [name, bytes] : corpus) {
    std::string why;
    EXPECT_FALSE(Decode(bytes, &why)) << name;
    EXPECT_FALSE(why.empty()) << name;
    EXPECT_EQ(why.find('\n'), std::string::npos) << name;
  }
  EXPECT_GE(corpus.size(), 27u);
}

TEST(CommandModelAllowed, OnlyRegularFilesUnderTheModelFolders) {
  const std::string dir = ::testing::TempDir() + "saccade_models_" + std::to_string(getpid());
  fs::create_directories(dir + "/models");
  std::ofstream(dir + "/models/mug.pcd") << "x";
  std::ofstream(dir + "/secret.pcd") << "x";
  fs::create_symlink(dir + "/secret.pcd", dir + "/models/link.pcd");
  ASSERT_EQ(mkfifo((dir + "/models/pipe.pcd").c_str(), 0600), 0);
  const std::vector<std::string> dirs = {dir + "/models"};
  std::string why;
  EXPECT_TRUE(CommandModelAllowed(dir + "/models/mug.pcd", dirs, &why)) << why;
  EXPECT_TRUE(CommandModelAllowed("synthetic:target", dirs, &why)) << why;
  for (const std::string& bad :
       {dir + "/secret.pcd", dir + "/models/../secret.pcd", dir + "/models/link.pcd",
        dir + "/models/pipe.pcd", dir + "/models", std::string("/dev/zero"),
        std::string("/proc/self/mem"), dir + "/models/none.pcd", std::string("capture:x.yaml")}) {
    EXPECT_FALSE(CommandModelAllowed(bad, dirs, &why)) << bad;
    EXPECT_NE(why.find("SWITCH_MODEL: "), std::string::npos) << why;
  }
  EXPECT_FALSE(CommandModelAllowed(dir + "/models/mug.pcd", {}, &why));
  EXPECT_NE(why.find("model folders: none"), std::string::npos) << why;
}

TEST(CommandModelAllowed, ALongPathIsEchoedCutWithItsLength) {
  // The longest path a command may carry (4,096 bytes): the refusal is one short line.
  const std::string path = "/nonexistent/" + std::string(4000, 'a') + ".pcd";
  std::string why;
  EXPECT_FALSE(CommandModelAllowed(path, {"/models"}, &why));
  EXPECT_LE(why.size(), 420u) << why;
  EXPECT_EQ(why.rfind("SWITCH_MODEL: no such file '/nonexistent/aaa", 0), 0u) << why;
  EXPECT_NE(why.find(" characters cut of "), std::string::npos) << why;
  EXPECT_EQ(why.substr(why.size() - 10), "aaaaa.pcd'") << why;  // the tail kept
}

TEST(LogLimiter, AtMostNLinesASecondAndTheNextSaysHowManyWereHeldBack) {
  LogLimiter limiter(2);
  const auto t0 = LogLimiter::Clock::time_point() + std::chrono::hours(1);
  std::int64_t held = -1;
  EXPECT_TRUE(limiter.Allow(&held, t0));
  EXPECT_EQ(held, 0);
  EXPECT_TRUE(limiter.Allow(&held, t0 + std::chrono::milliseconds(10)));
  for (int i = 0; i < 7; ++i)
    EXPECT_FALSE(limiter.Allow(&held, t0 + std::chrono::milliseconds(20)));
  EXPECT_TRUE(limiter.Allow(&held, t0 + std::chrono::milliseconds(1000)));
  EXPECT_EQ(held, 7);
  EXPECT_TRUE(limiter.Allow(&held, t0 + std::chrono::milliseconds(1001)));
  EXPECT_EQ(held, 0);
}

}  // namespace
}  // namespace saccade
