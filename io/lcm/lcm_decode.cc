#include "io/lcm/lcm_decode.h"

#include "io/lcm/lcm_log.h"

#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include <cstdint>
#include <initializer_list>

namespace saccade {
namespace {

// Each type's fields after its 8-byte type hash (nested structs carry no hash), up to its
// count; then the nested type's.
constexpr std::initializer_list<int> kDetectionsLayout = {8,  8, 8, 8, kLcmString, 1,
                                                          24, 8, 8, 4, 4,          4};
constexpr std::initializer_list<int> kInstanceLayout = {8, 4, kLcmString, 24, 32, 24, 24,        4,
                                                        4, 4, 4,          4,  4,  1,  kLcmString};
constexpr std::size_t kSmallestInstance = 8 + 4 + 5 + 24 + 32 + 24 + 24 + 4 + 16 + 4 + 1 + 5;
constexpr std::initializer_list<int> kFixationLayout = {
    8, 8, 8, kLcmString, 24, 24, 8, 1, kLcmString, 4, 4, 4, kLcmString};
constexpr std::initializer_list<int> kStatusLayout = {8, 8, kLcmString, kLcmString, 1, 8, 8, 8, 8,
                                                      8, 8, 4,          8,          8, 8, 4, 1, 4};
constexpr std::initializer_list<int> kStageLayout = {8, kLcmString, 4, 4, 4, 4, 4};
constexpr std::size_t kSmallestStage = 8 + 5 + 4 + 16;

// The fields, then `count` (the int32 ending them) nested items: each within the bytes, the
// count checked against what is left before lcm-gen's decoder sizes a vector by it.
bool Fits(const void* data, std::size_t size, std::initializer_list<int> layout,
          std::initializer_list<int> item, std::size_t smallest_item) {
  const auto* d = static_cast<const unsigned char*>(data);
  std::size_t at = 8;
  if (!LcmFieldsFit(d, size, &at, layout)) return false;
  if (item.size() == 0) return true;
  const std::int32_t count = LcmInt32(d + at - 4);
  if (count < 0 || static_cast<std::size_t>(count) > (size - at) / smallest_item) return false;
  for (std::int32_t i = 0; i < count; ++i)
    if (!LcmFieldsFit(d, size, &at, item)) return false;
  return true;
}

template <typename Message>
std::optional<Message> Decode(const void* data, std::size_t size, bool fits) {
  if (!fits) return std::nullopt;
  Message m;
  if (m.decode(data, 0, static_cast<int>(size)) < 0) return std::nullopt;
  return m;
}

}  // namespace

std::optional<detections_t> DecodeDetectionsMessage(const void* data, std::size_t size) {
  return Decode<detections_t>(
      data, size, Fits(data, size, kDetectionsLayout, kInstanceLayout, kSmallestInstance));
}

std::optional<fixation_t> DecodeFixationMessage(const void* data, std::size_t size) {
  return Decode<fixation_t>(data, size, Fits(data, size, kFixationLayout, {}, 1));
}

std::optional<status_t> DecodeStatusMessage(const void* data, std::size_t size) {
  return Decode<status_t>(data, size,
                          Fits(data, size, kStatusLayout, kStageLayout, kSmallestStage));
}

}  // namespace saccade
