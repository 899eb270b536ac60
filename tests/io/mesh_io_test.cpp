// Reading and writing meshes for the tools and tests (vcg_ext/io/mesh_io.h).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "vcg_ext/io/mesh_io.h"
#include "test_support.h"

// An OFF file with comments, an empty line and a line of spaces between the vertices and the
// faces (the data set's prim.off has one: vcglib's tokenizer read it as a line without tokens
// and crashed), a triangle and a quad: every vertex and face is read, the quad as two
// triangles.
TEST(MeshIo, OffWithBlankLinesIsRead) {
  const std::string path = testsupport::ScratchDir() + "/blank_lines.off";
  {
    std::ofstream o(path);
    o << "OFF\n# a comment\n5 2 0\n\n0 0 0\n1 0 0\n  \t\n1 1 0\n0 1 0\n0 0 1\n   \n# faces\n"
         "3 0 1 4\n4 0 1 2 3\n\n";
  }
  vcgext::TMesh m;
  ASSERT_EQ(vcgext::LoadMesh(path, m), "");
  EXPECT_EQ(m.vn, 5);
  EXPECT_EQ(m.fn, 3);
  EXPECT_DOUBLE_EQ(m.vert[4].P()[2], 1.0);
  EXPECT_NE(vcgext::LoadMesh(testsupport::ScratchDir() + "/missing.off", m), "");
}
