// Per-stage peak memory (core/memory.h): a stage that touches a large buffer reports it, the
// next stage (after the buffer is freed) does not, and the process peak remembers both.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "vcg_ext/core/memory.h"

TEST(Memory, StagePeaksAreSeparateAndTheProcessPeakRemembersThem) {
  vcgext::StagePeakMemoryMb();  // start a stage
  const size_t bytes = size_t(256) << 20;
  {
    std::unique_ptr<char[]> big(new char[bytes]);
    std::memset(big.get(), 1, bytes);  // resident, not just reserved
    EXPECT_NE(big[bytes / 2], 0);
  }
  const double withBuffer = vcgext::StagePeakMemoryMb();
  EXPECT_GT(withBuffer, 256.0);
  const double after = vcgext::StagePeakMemoryMb();  // a stage that allocated nothing
  // Linux resets the high-water mark between stages (/proc/self/clear_refs); elsewhere every
  // stage reports the process peak so far.
  if (after < withBuffer) {
    EXPECT_LT(after, withBuffer - 200.0);
  }
  EXPECT_GE(vcgext::ProcessPeakMemoryMb(), withBuffer);
}
