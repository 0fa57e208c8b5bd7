// saccade keygen: the key that signs saccaded's commands. saccade command: one command sent to a
// running saccaded, signed when a key is at hand (docs/LCM.md, "Signed commands").

#include "core/fail.h"
#include "daemon/args.h"
#include "daemon/cli/commands.h"
#include "daemon/exit_codes.h"
#include "io/base/text.h"
#include "io/lcm/bus.h"
#include "io/lcm/command_key.h"
#include "io/lcm/lcm_open.h"

#include <lcm/lcm-cpp.hpp>
#include <saccade/command_t.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ostream>
#include <random>

namespace saccade {

int RunKeygen(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade keygen",
            "Makes the key that signs saccaded's commands: 32 random bytes as 64 hexadecimal "
            "digits, mode 0600. saccaded acts only on commands signed with it once it exists "
            "(lcm.commands: auto or signed); each program that sends commands needs a copy "
            "(docs/LCM.md, \"Signed commands\").");
  args.Value("out", "PATH",
             std::string("where the key goes (default: ") + kDefaultCommandKeyPath + ")")
      .Value("owner", "USER", "the user the key file belongs to (saccaded's: saccade)")
      .Switch("force", "replace a key that is there (every sender then needs the new one)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  const std::string path = args.Get("out", kDefaultCommandKeyPath);
  std::string error;
  if (!WriteCommandKey(path, args.Get("owner", ""), args.Has("force"), &error)) {
    err << "saccade keygen: " << error << "\n";
    return kExitFailure;
  }
  out << "saccade keygen: wrote " << path << " (mode 0600"
      << (args.Has("owner") ? ", owner " + args.Get("owner") : std::string()) << ")\n";
  return kExitOk;
}

namespace {

bool ParseCoordinate(const std::string& text, double* value) {
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return !text.empty() && end && *end == '\0' && std::isfinite(*value);
}

}  // namespace

int RunSendCommand(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Args args("saccade command",
            "Sends one command to a running saccaded: fovea X Y Z (metres, in its published "
            "frame), reset, switch M.pcd, pause or resume. Signed with the key when there is "
            "one (--key, or the default key file when it exists), as saccaded asks once a key "
            "exists. Whether it was acted on shows in saccaded's status (commands_accepted, "
            "commands_rejected) and log.");
  args.Positional("KIND", "fovea | reset | switch | pause | resume")
      .Positional("ARG1", "fovea: X; switch: the model file")
      .Positional("ARG2", "fovea: Y")
      .Positional("ARG3", "fovea: Z")
      .Value("key", "PATH",
             std::string("the command key (default: ") + kDefaultCommandKeyPath +
                 " when it exists, else the command goes unsigned)")
      .Value("lcm-url", "URL", "the LCM network (default: saccaded's)")
      .Value("channel-prefix", "PREFIX", "saccaded's lcm.channel_prefix (default: SACCADE)");
  if (auto code = args.Parse(argv, out, err)) return *code;
  const std::string kind = args.Get("KIND", "");
  saccade::command_t m{};
  m.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                std::chrono::system_clock::now().time_since_epoch())
                .count();
  m.sequence = static_cast<std::int64_t>(std::random_device{}() & 0x7fffffff);
  m.model = "";
  const int needed = kind == "fovea" ? 3 : kind == "switch" ? 1 : 0;
  if (kind == "fovea") {
    m.kind = saccade::command_t::SET_FOVEA;
    for (int i = 0; i < 3; ++i) {
      const std::string name = "ARG" + std::to_string(i + 1);
      if (!args.Has(name) || !ParseCoordinate(args.Get(name), &m.fovea[i]))
        return Usage(err, "command", "fovea takes three finite numbers: X Y Z in metres");
    }
  } else if (kind == "switch") {
    m.kind = saccade::command_t::SWITCH_MODEL;
    if (!args.Has("ARG1")) return Usage(err, "command", "switch takes the model file");
    m.model = args.Get("ARG1");
    if (m.model.size() > 4095) return Usage(err, "command", "a model path of at most 4095 bytes");
  } else if (kind == "reset") {
    m.kind = saccade::command_t::RESET;
  } else if (kind == "pause") {
    m.kind = saccade::command_t::PAUSE;
  } else if (kind == "resume") {
    m.kind = saccade::command_t::RESUME;
  } else {
    return Usage(err, "command",
                 "the first argument must be fovea, reset, switch, pause or resume");
  }
  if (args.Has("ARG" + std::to_string(needed + 1)))
    return Usage(err, "command", kind + " takes " + std::to_string(needed) + " argument(s)");

  std::string error;
  const std::string key_path = args.Get("key", kDefaultCommandKeyPath);
  const bool sign = args.Has("key") || PathExists(key_path);
  Digest key{};
  if (sign && !ReadCommandKey(key_path, &key, &error)) {
    err << "saccade command: " << error << "\n";
    return kExitFailure;
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  if (sign) SignCommand(key, &bytes);

  const std::string url = args.Get("lcm-url", BusOptions{}.url);
  std::unique_ptr<lcm::LCM> lcm = OpenLcm(url, &error);
  if (!lcm) {
    err << "saccade command: " << error << "\n";
    return kExitFailure;
  }
  const std::string channel = CommandChannel(args.Get("channel-prefix", "SACCADE"));
  if (lcm->publish(channel, bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
    err << "saccade command: LCM did not send it on " << channel << " at " << url << "\n";
    return kExitFailure;
  }
  out << "saccade command: sent " << kind << " on " << channel << (sign ? ", signed" : ", unsigned")
      << "\n";
  return kExitOk;
}

}  // namespace saccade
