// The exit codes of saccade and saccaded: 0 success, 1 the input could not be processed (file,
// cloud, model, device), 2 bad usage (flags, configuration).
#pragma once

namespace saccade {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

}  // namespace saccade
