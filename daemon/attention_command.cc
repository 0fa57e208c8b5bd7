#include "daemon/attention_command.h"

namespace saccade {

void ApplyFixationCommand(const Command& command, const Eigen::Vector3f& initial_fovea_m,
                          Attention* attention) {
  if (command.kind == Command::Kind::kSetFovea)
    attention->Reset(command.fovea_m, "command", /*aimed=*/true);
  else if (command.kind == Command::Kind::kReset)
    attention->Reset(initial_fovea_m, "reset");
}

}  // namespace saccade
