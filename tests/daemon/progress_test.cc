// The progress line of long commands: its text, and that it is drawn on a terminal only.
#include "daemon/cli/progress.h"

#include <gtest/gtest.h>

#include <sstream>

namespace saccade {
namespace {

TEST(ProgressLine, SaysWhatIsDoneAndTheTimeLeft) {
  EXPECT_EQ(ProgressLine::Text("eval", 0, 212, 0.0), "eval: 0/212 (0%)");
  // 37 in 40 s: 175 more at the same pace take 189 s.
  EXPECT_EQ(ProgressLine::Text("eval", 37, 212, 40.0), "eval: 37/212 (17%), 3:09 left");
  EXPECT_EQ(ProgressLine::Text("eval", 1, 212, 60.0), "eval: 1/212 (0%), 3:31:00 left");
  EXPECT_EQ(ProgressLine::Text("eval", 212, 212, 300.0), "eval: 212/212 (100%), 0:00 left");
  EXPECT_EQ(ProgressLine::Text("record: frames", 12, 0, 3.0), "record: frames: 12 done");
}

TEST(ProgressLine, DrawsOnATerminalOnlyAndClearsItsLine) {
  std::ostringstream log, terminal;
  {
    ProgressLine plain(log, false), drawn(terminal, true);
    for (std::size_t i = 0; i <= 3; ++i) {
      plain.Show("frames", i, 3);
      drawn.Show("frames", i, 3);
    }
  }
  EXPECT_EQ(log.str(), "");
  const std::string t = terminal.str();
  EXPECT_EQ(t.rfind("\rframes: 0/3 (0%)", 0), 0u) << t;
  EXPECT_NE(t.find("\rframes: 3/3 (100%), 0:00 left"), std::string::npos) << t;  // the last step
  EXPECT_EQ(t.back(), '\r') << "cleared at the end";
  EXPECT_EQ(t.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace saccade
