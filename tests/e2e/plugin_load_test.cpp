// The installed plugin loads in meshlabserver and in the MeshLab GUI (under Xvfb) without errors.
#include <gtest/gtest.h>


#include "e2e_support.h"

TEST(PluginLoad, GuiLoadsPluginWithoutErrors) {
  // QT_DEBUG_PLUGINS makes Qt print every plugin it loads (and why one fails); the GUI is
  // killed after a few seconds, which is enough for its start-up plugin scan.
  std::string scratch = e2e::OutPath("gui");
  // The GUI runs for 10 s inside xvfb-run's X server, then is terminated (xvfb-run cleans up).
  auto r = e2e::Run("mkdir -p " + e2e::Q(scratch) + "/run && chmod 700 " + e2e::Q(scratch) +
                    "/run && XDG_CONFIG_HOME=" + e2e::Q(scratch) + " XDG_CACHE_HOME=" + e2e::Q(scratch) +
                    " XDG_RUNTIME_DIR=" + e2e::Q(scratch) + "/run QT_DEBUG_PLUGINS=1 "
                    "xvfb-run -a -s '-screen 0 1280x1024x24' sh -c 'meshlab & p=$!; sleep 10; "
                    "kill $p; wait $p; true'");
  EXPECT_NE(r.output.find("libfilter_fitmap_quad.so"), std::string::npos) << r.output.substr(0, 4000);
  EXPECT_NE(r.output.find("loaded library"), std::string::npos);
  // No load failure that names our plugin.
  for (const char* bad : {"Cannot load library", "undefined symbol", "not a valid Qt plugin"}) {
    size_t pos = r.output.find(bad);
    while (pos != std::string::npos) {
      std::string line = r.output.substr(pos, r.output.find('\n', pos) - pos);
      EXPECT_EQ(line.find("fitmap"), std::string::npos) << line;
      pos = r.output.find(bad, pos + 1);
    }
  }
}

TEST(PluginLoad, MeshlabserverListsOurFilters) {
  // meshlabserver -d dumps the filter list with its documentation: our filters must be there.
  std::string dump = e2e::OutPath("filters_dump.txt");
  auto r = e2e::Meshlabserver("-d " + e2e::Q(dump));
  const std::string text = e2e::Slurp(dump);
  EXPECT_NE(text.find("Compute Fitmaps"), std::string::npos) << r.output.substr(0, 2000);
}
