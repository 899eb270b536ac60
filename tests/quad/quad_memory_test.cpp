// Fitmap Quad Simplification's memory (core/pipeline_memory.h): a mesh above the budget is refused
// before the simplification starts.
#include <gtest/gtest.h>

#include <string>

#include "test_support.h"
#include "vcg_ext/core/pipeline_memory.h"
#include "vcg_ext/quad/quad_simplify.h"

using vcgext::PipelineStep;

TEST(QuadSimplifyMemory, SimplificationAboveTheBudgetIsRefusedBeforeItStarts) {
  vcgext::TMesh m;
  testsupport::ToVcg(testsupport::Icosphere(3), m);
  vcgext::QuadSimplifyParams p;
  p.maxMemoryMb = 0.9 * vcgext::EstimatePipelineMemoryMb(PipelineStep::Simplification, m.fn);
  const std::string err = vcgext::SimplifyToQuads(m, p).error;  // refused before it asks for the Fitmaps
  EXPECT_NE(err.find("a layer of 1280 triangles would need about"), std::string::npos) << err;
  p.maxMemoryMb = 0;
  EXPECT_NE(vcgext::SimplifyToQuads(m, p).error.find("compute the Fitmaps first"), std::string::npos);
}

