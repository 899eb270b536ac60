// scripts/meshlabserver.sh returns meshlabserver's own exit status, not xvfb-run's: xvfb-run exits 5
// when it cannot remove its temporary folder after the command has finished, which once made the
// corpus test count a finished run as a crash. Stand-ins for xvfb-run and meshlabserver on PATH
// play each side, so every combination is tested without an X server.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "e2e_support.h"
#include "test_support.h"

namespace {

void WriteExecutable(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  std::filesystem::permissions(path, std::filesystem::perms::owner_all);
}

/// A folder with a stand-in xvfb-run (skips its options, runs the command, then exits `xvfbRc`
/// whatever the command returned) and a stand-in meshlabserver (prints its arguments, exits
/// `serverRc`; "none": xvfb-run fails before running it, as when Xvfb cannot start).
std::string FakeBin(const std::string& name, int xvfbRc, const std::string& serverRc) {
  const std::string dir = e2e::OutPath(name);
  std::filesystem::create_directories(dir);
  const bool run = serverRc != "none";
  WriteExecutable(dir + "/xvfb-run",
                  "#!/bin/sh\n"
                  "while [ \"${1#-}\" != \"$1\" ]; do case \"$1\" in -s) shift 2;; *) shift;; esac; done\n" +
                      std::string(run ? "\"$@\"\n" : "echo 'xvfb-run: error: Xvfb failed to start' >&2\n") +
                      "exit " + std::to_string(xvfbRc) + "\n");
  WriteExecutable(dir + "/meshlabserver",
                  "#!/bin/sh\necho \"stand-in meshlabserver $*\"\nexit " + (run ? serverRc : "0") + "\n");
  return dir;
}

e2e::RunResult RunWrapper(const std::string& bin) {
  return e2e::Run("PATH=" + e2e::Q(bin) + ":\"$PATH\" " +
                  e2e::Q(std::string(FITMAP_SOURCE_DIR) + "/scripts/meshlabserver.sh") + " -i in.ply -o out.ply");
}

TEST(MeshlabserverWrapper, ACleanUpFailureAfterASuccessfulRunIsNotAFailure) {
  auto r = RunWrapper(FakeBin("wrap_ok_cleanup5", 5, "0"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("stand-in meshlabserver -i in.ply -o out.ply"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warning: xvfb-run exited 5"), std::string::npos) << r.output;
}

TEST(MeshlabserverWrapper, MeshlabserversOwnFailureIsReturned) {
  // exit(-1) is 255; a clean-up failure on top must not hide it
  auto r = RunWrapper(FakeBin("wrap_fail_cleanup5", 5, "255"));
  EXPECT_EQ(r.exitCode, 255) << r.output;
  auto s = RunWrapper(FakeBin("wrap_fail", 255, "255"));
  EXPECT_EQ(s.exitCode, 255) << s.output;
  EXPECT_EQ(s.output.find("warning"), std::string::npos) << s.output;
}

TEST(MeshlabserverWrapper, XvfbRunsFailureIsReturnedWhenMeshlabserverNeverRan) {
  auto r = RunWrapper(FakeBin("wrap_noserver", 1, "none"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_EQ(r.output.find("stand-in meshlabserver"), std::string::npos) << r.output;
}

TEST(MeshlabserverWrapper, ASuccessfulRunExitsZeroWithoutWarning) {
  auto r = RunWrapper(FakeBin("wrap_ok", 0, "0"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
}

}  // namespace
