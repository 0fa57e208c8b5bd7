// What SET_FOVEA and RESET do to the attention loop: one function for saccaded's attention stage
// (AttendStage, daemon/stages.cc) and the command fuzz target (tests/fuzz/command_fuzz.cc).
#pragma once

#include "attention/attention.h"
#include "io/lcm/bus.h"

#include <Eigen/Core>

namespace saccade {

/// SET_FOVEA: the loop starts over looking at the command's fovea ("command"); RESET: at
/// `initial_fovea_m` ("reset"). Any other command leaves it. attention->current() is then the
/// fixation the next frame is foveated with.
void ApplyFixationCommand(const Command& command, const Eigen::Vector3f& initial_fovea_m,
                          Attention* attention);

}  // namespace saccade
