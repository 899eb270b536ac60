#include "e2e_support.h"

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>

#include "test_support.h"

namespace e2e {

RunResult Run(const std::string& cmd) {
  RunResult r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  int st = pclose(p);
  r.exitCode = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string Q(const std::string& s) {
  std::string o = "'";
  for (char c : s) o += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

RunResult Meshlabserver(const std::string& args) {
  return Run(Q(std::string(FITMAP_SOURCE_DIR) + "/scripts/meshlabserver.sh") + " " + args);
}

std::string Slurp(const std::string& path) {
  std::ifstream f(path);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

double JsonNumber(const std::string& json, const std::string& key) {
  std::smatch m;
  std::regex re("\"" + key + "\"\\s*:\\s*([-0-9.eE+]+)");
  if (!std::regex_search(json, m, re)) return NAN;
  return std::stod(m[1]);
}

int LoggedPatches(const std::string& log) {
  std::smatch m;
  return std::regex_search(log, m, std::regex("-> ([0-9]+) patches")) ? std::stoi(m[1]) : -1;
}

std::string OutPath(const std::string& name) { return testsupport::ScratchDir() + "/" + name; }

std::string ScriptWithFirstFilter(const std::string& script, const std::string& filterXml, const std::string& name) {
  const std::string s =
      std::regex_replace(Slurp(Script(script)), std::regex("<FilterScript>\n"), "<FilterScript>\n" + filterXml);
  const std::string path = OutPath(name);
  std::ofstream(path) << s;
  return path;
}

std::vector<std::string> MlxScripts() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(std::string(FITMAP_SOURCE_DIR) + "/meshlab_scripts"))
    if (e.path().extension() == ".mlx") out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string Script(const std::string& name) { return std::string(FITMAP_SOURCE_DIR) + "/meshlab_scripts/" + name; }

}  // namespace e2e
