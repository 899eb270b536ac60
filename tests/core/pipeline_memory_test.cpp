// The quad pipeline's memory estimates and budget (core/pipeline_memory.h, core/memory.h): the
// estimates grow with the input, the refusal names what to do, and FITMAP_MAX_MEMORY_MB lowers the
// budget. The refusals themselves: fitmaps/fitmaps_memory_test.cpp, quad/quad_memory_test.cpp.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "vcg_ext/core/memory.h"
#include "vcg_ext/core/pipeline_memory.h"

using vcgext::PipelineStep;

TEST(PipelineMemory, EstimatesGrowWithTheInputAndTheFitNamesTheReference) {
  for (PipelineStep s : {PipelineStep::Fitmaps, PipelineStep::Simplification, PipelineStep::FitAndBake}) {
    const double small = vcgext::EstimatePipelineMemoryMb(s, 1e5), large = vcgext::EstimatePipelineMemoryMb(s, 1e7);
    EXPECT_GT(small, 0);
    EXPECT_GT(large, 20 * small) << "nearly proportional to the triangles";
  }
  // 40 M triangles: more than this suite would ever be allowed
  const std::string err = vcgext::CheckPipelineMemory(PipelineStep::FitAndBake, 4e7, 1000);
  EXPECT_NE(err.find("a reference layer of 40000000 triangles would need about 22.3 GB of memory, more than the "
                     "1000 MB allowed: decimate the reference layer first"),
            std::string::npos)
      << err;
}

TEST(PipelineMemory, EnvironmentLowersTheBudget) {
  ASSERT_EQ(::setenv("FITMAP_MAX_MEMORY_MB", "10", 1), 0);
  const std::string capped = vcgext::CheckMemory(20, 0, "twenty");
  const std::string fits = vcgext::CheckMemory(5, 0, "five");
  const std::string given = vcgext::CheckMemory(20, 30, "given");  // a budget passed in wins
  ::unsetenv("FITMAP_MAX_MEMORY_MB");
  EXPECT_EQ(capped, "twenty would need about 20 MB of memory, more than the 10 MB allowed");
  EXPECT_EQ(fits, "");
  EXPECT_EQ(given, "");
  if (vcgext::AvailableMemoryMb() > 0) {  // no limit set: what the machine has
    const std::string err = vcgext::CheckMemory(1e9, 0, "a petabyte");
    EXPECT_NE(err.find(" available"), std::string::npos) << err;
  }
}
