// Where the tests find the shared real Kinect data, and a skip when it is missing.
#pragma once

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <string>

namespace saccade::testing {

inline std::string DataPath(const std::string& relative) {
  return std::string(SACCADE_DATA_DIR) + "/" + relative;
}

inline bool DataPresent(const std::string& relative) {
  struct stat st {};
  return stat(DataPath(relative).c_str(), &st) == 0;
}

}  // namespace saccade::testing

/// Skips the current test, saying why, when a file of ../shared/data is missing.
#define SACCADE_REQUIRE_DATA(relative)                                                \
  do {                                                                                \
    if (!::saccade::testing::DataPresent(relative))                                   \
      GTEST_SKIP() << "real data missing: " << ::saccade::testing::DataPath(relative) \
                   << " (see ../shared/data/README.md)";                              \
  } while (0)
