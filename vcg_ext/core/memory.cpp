#include "vcg_ext/core/memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace vcgext {

namespace {
std::atomic<double> g_processPeakMb{0.0};

// The value (kB) of the line starting with `key` in the /proc file `path`, else -1.
long ProcKb(const char* path, const char* key) {
  long kb = -1;
  const size_t n = std::strlen(key);
  if (FILE* f = std::fopen(path, "r")) {
    char line[256];
    while (std::fgets(line, sizeof line, f))
      if (std::strncmp(line, key, n) == 0) { kb = std::strtol(line + n, nullptr, 10); break; }
    std::fclose(f);
  }
  return kb;
}

/// VmHWM of /proc/self/status in MB; getrusage's peak where /proc is missing.
double HighWaterMb() {
  const long kb = ProcKb("/proc/self/status", "VmHWM:");
  if (kb >= 0) return kb / 1024.0;
  struct rusage ru;
  return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss / 1024.0 : 0.0;
}

void RememberProcessPeak(double mb) {
  double old = g_processPeakMb.load();
  while (mb > old && !g_processPeakMb.compare_exchange_weak(old, mb)) {
  }
}
}  // namespace

double StagePeakMemoryMb() {
  const double peak = HighWaterMb();
  RememberProcessPeak(peak);
  if (FILE* f = std::fopen("/proc/self/clear_refs", "w")) {  // reset the mark: the next stage starts afresh
    std::fputs("5", f);
    std::fclose(f);
  }
  return peak;
}

double ResidentMemoryMb() {
  const long kb = ProcKb("/proc/self/status", "VmRSS:");
  return kb > 0 ? kb / 1024.0 : 0.0;
}

double AvailableMemoryMb() {
  const long kb = ProcKb("/proc/meminfo", "MemAvailable:");
  return kb > 0 ? kb / 1024.0 : 0.0;
}

std::string CheckMemory(double needMb, double budgetMb, const std::string& what) {
  const char* env = std::getenv("FITMAP_MAX_MEMORY_MB");
  const double cap = budgetMb > 0 ? budgetMb : env ? std::atof(env) : 0.0;  // a limit set: "allowed"
  const double available = 0.8 * AvailableMemoryMb();
  const bool capped = cap > 0 && (budgetMb > 0 || !(available > 0) || cap < available);
  const double budget = capped ? cap : available;
  if (!(budget > 0) || needMb <= budget) return {};
  auto size = [](double mb) {
    char buf[32];
    if (mb >= 1024) std::snprintf(buf, sizeof buf, "%.1f GB", mb / 1024.0);
    else std::snprintf(buf, sizeof buf, "%.0f MB", std::ceil(mb));
    return std::string(buf);
  };
  return what + " would need about " + size(needMb) + " of memory, more than the " + size(budget) +
         (capped ? " allowed" : " available");
}

double ProcessPeakMemoryMb() {
  RememberProcessPeak(HighWaterMb());
  return g_processPeakMb.load();
}

}  // namespace vcgext
