// saccaded's LCM messages decoded from bytes that may lie (a log, the network): each message's
// layout is walked first (lcm_log.h: every string's length and every count within the bytes),
// since lcm-gen's decoders trust them. The log converters, the viewer and `saccade mcap` read
// through these.
#pragma once

#include <cstddef>
#include <optional>

namespace saccade {

class detections_t;
class fixation_t;
class status_t;

/// The message, or nullopt when the bytes are not one.
std::optional<detections_t> DecodeDetectionsMessage(const void* data, std::size_t size);
std::optional<fixation_t> DecodeFixationMessage(const void* data, std::size_t size);
std::optional<status_t> DecodeStatusMessage(const void* data, std::size_t size);

}  // namespace saccade
