// Signed commands without a daemon: the HMAC against another implementation's answer, the key
// file's rules, the gate's verdicts (unsigned, wrong key, changed, stale, replayed), and which
// mode `lcm.commands: auto` comes to.
#include "io/lcm/command_key.h"
#include "io/lcm/bus.h"

#include <saccade/command_t.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace saccade {
namespace {

namespace fs = std::filesystem;

std::string Hex(const Digest& d) {
  std::string s;
  char b[3];
  for (const std::uint8_t x : d) {
    std::snprintf(b, sizeof b, "%02x", x);
    s += b;
  }
  return s;
}

Digest CountingKey(std::uint8_t first) {
  Digest key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(first + i);
  return key;
}

std::vector<std::uint8_t> Encode(const saccade::command_t& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

saccade::command_t Pause(std::int64_t utime, std::int64_t sequence) {
  saccade::command_t m{};
  m.utime = utime;
  m.sequence = sequence;
  m.kind = saccade::command_t::PAUSE;
  return m;
}

std::string TempFolder(const std::string& name) {
  const std::string dir =
      ::testing::TempDir() + "saccade_key_" + name + "_" + std::to_string(getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

unsigned Mode(const std::string& path) {
  struct stat st {};
  stat(path.c_str(), &st);
  return st.st_mode & 07777;
}

TEST(CommandKey, TheHmacIsPythonsHmacSha256) {
  // python3 -c "import hmac,hashlib; print(hmac.new(bytes(range(32)), b'saccade command',
  //             hashlib.sha256).hexdigest())"
  const std::string message = "saccade command";
  EXPECT_EQ(Hex(HmacSha256(CountingKey(0), message.data(), message.size())),
            "3c253fb31e261a09d61bf9c4b607a4d591e95e1a36b17f7f3269d6c6be1b3352");
}

TEST(CommandKey, KeygenWritesAPrivateKeyOnceAndForceMakesANewOne) {
  const std::string dir = TempFolder("keygen");
  const std::string path = dir + "/etc/command.key";  // its folder is made
  std::string error;
  ASSERT_TRUE(WriteCommandKey(path, "", false, &error)) << error;
  EXPECT_EQ(Mode(path), 0600u);
  EXPECT_FALSE(fs::exists(path + ".part"));
  Digest first{}, second{};
  ASSERT_TRUE(ReadCommandKey(path, &first, &error)) << error;
  EXPECT_FALSE(WriteCommandKey(path, "", false, &error));
  EXPECT_NE(error.find("a key is already there"), std::string::npos) << error;
  ASSERT_TRUE(ReadCommandKey(path, &second, &error)) << error;
  EXPECT_EQ(first, second);  // the refused keygen left the key alone
  ASSERT_TRUE(WriteCommandKey(path, "", true, &error)) << error;
  ASSERT_TRUE(ReadCommandKey(path, &second, &error)) << error;
  EXPECT_NE(first, second);
  EXPECT_FALSE(WriteCommandKey(dir + "/other.key", "no-such-user-here", false, &error));
  EXPECT_NE(error.find("no such user"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir + "/other.key"));
}

TEST(CommandKey, AKeyOthersCanReadOrThatIsNotAKeyIsRefused) {
  const std::string dir = TempFolder("bad");
  const auto write = [&](const std::string& name, const std::string& text, mode_t mode) {
    const std::string path = dir + "/" + name;
    std::ofstream(path) << text;
    chmod(path.c_str(), mode);
    return path;
  };
  const std::string hex64(64, 'a');
  Digest key{};
  std::string error;
  EXPECT_TRUE(ReadCommandKey(write("good", hex64 + "\n", 0600), &key, &error)) << error;
  EXPECT_EQ(key[0], 0xaa);
  EXPECT_FALSE(ReadCommandKey(write("open", hex64, 0644), &key, &error));
  EXPECT_NE(error.find("open to others (mode 0644): chmod 600"), std::string::npos) << error;
  EXPECT_FALSE(ReadCommandKey(write("group", hex64, 0640), &key, &error));
  for (const std::string& text : {std::string(""), std::string(63, 'a'), std::string(65, 'a'),
                                  std::string(62, 'a') + "zz", std::string(32, '\1')}) {
    EXPECT_FALSE(ReadCommandKey(write("short", text, 0600), &key, &error)) << text;
    EXPECT_NE(error.find("not a command key"), std::string::npos) << error;
  }
  EXPECT_FALSE(ReadCommandKey(dir, &key, &error));
  EXPECT_FALSE(ReadCommandKey(dir + "/none", &key, &error));
  EXPECT_NE(error.find("No such file"), std::string::npos) << error;
}

TEST(CommandGate, OnlyASignedFreshUnseenCommandPasses) {
  const Digest key = CountingKey(7);
  std::int64_t now = 1'800'000'000'000'000;  // microseconds since the epoch
  CommandGate gate(key, 30.0, [&now] { return now; });
  std::string why;

  std::vector<std::uint8_t> signed_pause = Encode(Pause(now - 2'000'000, 1));
  SignCommand(key, &signed_pause);
  EXPECT_TRUE(gate.Admit(signed_pause.data(), signed_pause.size(), &why)) << why;
  EXPECT_FALSE(gate.Admit(signed_pause.data(), signed_pause.size(), &why));
  EXPECT_NE(why.find("a replay"), std::string::npos) << why;

  std::vector<std::uint8_t> next = Encode(Pause(now - 2'000'000, 2));  // same time, next count
  SignCommand(key, &next);
  EXPECT_TRUE(gate.Admit(next.data(), next.size(), &why)) << why;

  const std::vector<std::uint8_t> unsigned_pause = Encode(Pause(now, 3));
  EXPECT_FALSE(gate.Admit(unsigned_pause.data(), unsigned_pause.size(), &why));
  EXPECT_EQ(why.rfind("unsigned", 0), 0u) << why;

  std::vector<std::uint8_t> other_key = Encode(Pause(now, 4));
  SignCommand(CountingKey(8), &other_key);
  EXPECT_FALSE(gate.Admit(other_key.data(), other_key.size(), &why));
  EXPECT_NE(why.find("a wrong signature"), std::string::npos) << why;

  std::vector<std::uint8_t> changed = Encode(Pause(now, 5));
  SignCommand(key, &changed);
  changed[24] = saccade::command_t::RESUME;  // the kind, after signing
  EXPECT_FALSE(gate.Admit(changed.data(), changed.size(), &why));
  EXPECT_NE(why.find("a wrong signature"), std::string::npos) << why;

  for (const std::int64_t skew : {-31'000'000LL, 31'000'000LL}) {
    std::vector<std::uint8_t> far = Encode(Pause(now + skew, 6));
    SignCommand(key, &far);
    EXPECT_FALSE(gate.Admit(far.data(), far.size(), &why)) << skew;
    EXPECT_NE(why.find("beyond lcm.command_max_age_s (30.0 s)"), std::string::npos) << why;
  }

  // Forty seconds on, the first command is refused as stale, not remembered for ever.
  now += 40'000'000;
  EXPECT_FALSE(gate.Admit(signed_pause.data(), signed_pause.size(), &why));
  EXPECT_NE(why.find("sent 42.0 s ago"), std::string::npos) << why;

  for (std::size_t size : {0u, 10u, 55u}) {
    EXPECT_FALSE(gate.Admit(signed_pause.data(), size, &why)) << size;
    EXPECT_EQ(why.rfind("unsigned", 0), 0u) << why;
  }
}

TEST(CommandGate, AutoIsSignedWithAKeyOpenOnThisHostAndOffBeyondIt) {
  const std::string dir = TempFolder("auto");
  BusOptions o;
  o.command_key = dir + "/command.key";
  o.url = "udpm://239.255.76.67:7667?ttl=0";
  EXPECT_EQ(o.Resolved(), BusOptions::Commands::kOpen);
  o.url = "udpm://239.255.76.67:7667";  // liblcm's default ttl is 0
  EXPECT_EQ(o.Resolved(), BusOptions::Commands::kOpen);
  o.url = "udpm://239.255.76.67:7667?recv_buf_size=100000&ttl=1";
  EXPECT_EQ(o.Resolved(), BusOptions::Commands::kOff);
  std::string error;
  ASSERT_TRUE(WriteCommandKey(o.command_key, "", false, &error)) << error;
  EXPECT_EQ(o.Resolved(), BusOptions::Commands::kSigned);

  o.commands = BusOptions::Commands::kOpen;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("allowed only with ttl=0"), std::string::npos) << error;
  o.url = "udpm://239.255.76.67:7667?ttl=0";
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.command_max_age_s = 0;
  EXPECT_FALSE(o.IsValid(&error));
}

}  // namespace
}  // namespace saccade
