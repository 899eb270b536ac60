// Replays fuzz_mesh inputs without libFuzzer (any compiler): every file named on the command
// line, or in a folder named there, goes through LLVMFuzzerTestOneInput once. The sanitizer build
// (FITMAP_SANITIZE) runs it as the ctest FuzzMesh.Replay on tests/fuzz/make_seeds.py's seeds
// and on the reproducers in tests/fuzz/regressions, so fuzz_mesh.cpp is built and run in CI.
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {
int Replay(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) { std::fprintf(stderr, "cannot read %s\n", path.c_str()); return 1; }
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::fprintf(stderr, "replaying %s (%zu bytes)\n", path.c_str(), bytes.size());
  LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  int failed = 0, replayed = 0;
  for (int a = 1; a < argc; ++a) {
    struct stat st;
    if (stat(argv[a], &st) != 0) { std::fprintf(stderr, "no such file: %s\n", argv[a]); ++failed; continue; }
    std::vector<std::string> files;
    if (S_ISDIR(st.st_mode)) {
      if (DIR* d = opendir(argv[a])) {
        while (dirent* e = readdir(d))
          if (e->d_name[0] != '.') files.push_back(std::string(argv[a]) + "/" + e->d_name);
        closedir(d);
      }
      std::sort(files.begin(), files.end());
    } else {
      files.push_back(argv[a]);
    }
    for (const auto& f : files) {
      failed += Replay(f);
      ++replayed;
    }
  }
  std::fprintf(stderr, "%d inputs replayed\n", replayed);
  return failed ? 1 : 0;
}
