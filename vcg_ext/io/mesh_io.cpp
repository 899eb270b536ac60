#include "vcg_ext/io/mesh_io.h"

#include <wrap/io_trimesh/export_obj.h>
#include <wrap/io_trimesh/export_off.h>
#include <wrap/io_trimesh/export_ply.h>
#include <wrap/io_trimesh/import_obj.h>
#include <wrap/io_trimesh/import_off.h>
#include <wrap/io_trimesh/import_ply.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

namespace vcgext {

namespace {
std::string Ext(const std::string& path) {
  auto dot = path.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

// A line of spaces, tabs or carriage returns only, not empty: vcglib's OFF tokenizer skips empty
// lines and comments but reads such a line as one without tokens and dereferences its first (a
// segfault on the data set's prim.off; MeshLab's reader opens it).
bool BlankLine(const std::string& line) {
  return !line.empty() && line.find_first_not_of(" \t\r") == std::string::npos;
}

// OFF file `path` into m: streamed by vcglib as it is (a scan of hundreds of MB is not held in
// memory), or, when it has blank lines (BlankLine), read from its text without them.
int OpenOff(const std::string& path, TMesh& m) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return vcg::tri::io::ImporterOFF<TMesh>::CantOpen;
  bool blank = false;
  for (std::string line; !blank && std::getline(in, line);) blank = BlankLine(line);
  if (!blank) return vcg::tri::io::ImporterOFF<TMesh>::Open(m, path.c_str());
  in.clear();
  in.seekg(0);
  std::ostringstream out;
  for (std::string line; std::getline(in, line);)
    if (!BlankLine(line)) out << line << '\n';
  const std::string text = out.str();
  int mask = 0;
  return vcg::tri::io::ImporterOFF<TMesh>::OpenMem(m, text.data(), text.size(), mask);
}
}  // namespace

std::string LoadMesh(const std::string& path, TMesh& m) {
  m.Clear();
  const std::string e = Ext(path);
  int err = 0;
  if (e == "off") {
    err = OpenOff(path, m);
    if (err) return std::string("cannot read OFF ") + path + ": " + vcg::tri::io::ImporterOFF<TMesh>::ErrorMsg(err);
  } else if (e == "ply") {
    err = vcg::tri::io::ImporterPLY<TMesh>::Open(m, path.c_str());
    if (err) return std::string("cannot read PLY ") + path + ": " + vcg::tri::io::ImporterPLY<TMesh>::ErrorMsg(err);
  } else if (e == "obj") {
    int mask = 0;
    err = vcg::tri::io::ImporterOBJ<TMesh>::Open(m, path.c_str(), mask);
    if (err && !vcg::tri::io::ImporterOBJ<TMesh>::ErrorCritical(err)) err = 0;
    if (err) return std::string("cannot read OBJ ") + path + ": " + vcg::tri::io::ImporterOBJ<TMesh>::ErrorMsg(err);
  } else {
    return "unsupported mesh format: " + path;
  }
  return "";
}

std::string SaveMesh(const std::string& path, TMesh& m, bool withQuality, bool withColor) {
  const std::string e = Ext(path);
  int mask = 0;
  if (withQuality) mask |= vcg::tri::io::Mask::IOM_VERTQUALITY;
  if (withColor) mask |= vcg::tri::io::Mask::IOM_VERTCOLOR;
  int err = 0;
  if (e == "ply") {
    mask |= vcg::tri::io::Mask::IOM_BITPOLYGONAL;
    err = vcg::tri::io::ExporterPLY<TMesh>::Save(m, path.c_str(), mask, true);
  } else if (e == "off") {
    err = vcg::tri::io::ExporterOFF<TMesh>::Save(m, path.c_str(), mask);
  } else if (e == "obj") {
    err = vcg::tri::io::ExporterOBJ<TMesh>::Save(m, path.c_str(), mask);
  } else {
    return "unsupported mesh format: " + path;
  }
  return err ? "cannot write " + path : "";
}

}  // namespace vcgext
