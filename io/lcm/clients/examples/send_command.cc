// Sends saccaded one signed command: send_command URL KEY_FILE pause|resume|reset|fovea X Y Z.
// The signature is HMAC-SHA256, with the 32-byte key of KEY_FILE (64 hexadecimal digits, made
// by saccade keygen), of every byte of the encoded command_t before its last 32, which it fills
// (docs/LCM.md, "Signed commands"). Builds with the lcm-gen headers and -lcrypto.
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/command_t.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: send_command URL KEY_FILE pause|resume|reset|fovea X Y Z\n");
    return 2;
  }
  std::string hex;
  std::ifstream(argv[2]) >> hex;
  if (hex.size() != 64) {
    std::fprintf(stderr, "%s: not a command key (64 hexadecimal digits)\n", argv[2]);
    return 1;
  }
  unsigned char key[32];
  for (int i = 0; i < 32; ++i)
    key[i] = static_cast<unsigned char>(std::stoi(hex.substr(2 * i, 2), nullptr, 16));

  saccade::command_t m{};
  m.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                std::chrono::system_clock::now().time_since_epoch())
                .count();
  m.sequence = 0;  // a program sending several commands counts them: 0, 1, 2, ...
  const std::string kind = argv[3];
  if (kind == "pause") {
    m.kind = saccade::command_t::PAUSE;
  } else if (kind == "resume") {
    m.kind = saccade::command_t::RESUME;
  } else if (kind == "reset") {
    m.kind = saccade::command_t::RESET;
  } else if (kind == "fovea" && argc == 7) {
    m.kind = saccade::command_t::SET_FOVEA;
    for (int i = 0; i < 3; ++i) m.fovea[i] = std::atof(argv[4 + i]);
  } else {
    std::fprintf(stderr, "unknown command '%s'\n", argv[3]);
    return 2;
  }

  // Encode with the signature zero, then sign every byte before it.
  std::vector<unsigned char> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const std::size_t body = bytes.size() - 32;
  unsigned int length = 0;
  HMAC(EVP_sha256(), key, 32, bytes.data(), body, bytes.data() + body, &length);

  lcm::LCM lcm(argv[1]);
  if (!lcm.good() ||
      lcm.publish("SACCADE_COMMAND", bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
    std::fprintf(stderr, "LCM did not send it\n");
    return 1;
  }
  std::printf("sent %s, signed\n", kind.c_str());
  return 0;
}
