#pragma once
/// End-to-end helpers: run the installed plugin through headless meshlabserver / meshlab.
#include <string>
#include <vector>

namespace e2e {

struct RunResult {
  int exitCode = -1;
  std::string output;  ///< stdout + stderr
};

/// Runs a shell command, capturing stdout+stderr.
RunResult Run(const std::string& cmd);
/// Runs scripts/meshlabserver.sh with `args` (already shell-quoted where needed).
RunResult Meshlabserver(const std::string& args);
/// `dir`/`name`, creating `dir` if needed.
std::string OutPath(const std::string& name);
/// All files in meshlab_scripts/ ending with .mlx (basenames, sorted).
std::vector<std::string> MlxScripts();
/// Absolute path of meshlab_scripts/<name>.
std::string Script(const std::string& name);
/// meshlab_scripts/<script> with the filter `filterXml` (a <filter> element) run first, written to
/// OutPath(`name`); returns its path.
std::string ScriptWithFirstFilter(const std::string& script, const std::string& filterXml, const std::string& name);
/// Quotes a string for /bin/sh.
std::string Q(const std::string& s);
/// The whole content of a file ("" if it cannot be read).
std::string Slurp(const std::string& path);
/// The number after `"key":` in a JSON text (report.json is flat enough), NaN if absent.
double JsonNumber(const std::string& json, const std::string& key);
/// The patches the simplification's log reports ("N -> P patches"), -1 if absent.
int LoggedPatches(const std::string& log);

}  // namespace e2e
