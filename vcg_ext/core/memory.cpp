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

/// VmHWM of /proc/self/status in MB; getrusage's peak where /proc is missing.
double HighWaterMb() {
  if (FILE* f = std::fopen("/proc/self/status", "r")) {
    char line[256];
    long kb = -1;
    while (std::fgets(line, sizeof line, f))
      if (std::strncmp(line, "VmHWM:", 6) == 0) { kb = std::strtol(line + 6, nullptr, 10); break; }
    std::fclose(f);
    if (kb >= 0) return kb / 1024.0;
  }
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

double AvailableMemoryMb() {
  long kb = -1;
  if (FILE* f = std::fopen("/proc/meminfo", "r")) {
    char line[256];
    while (std::fgets(line, sizeof line, f))
      if (std::strncmp(line, "MemAvailable:", 13) == 0) { kb = std::strtol(line + 13, nullptr, 10); break; }
    std::fclose(f);
  }
  return kb > 0 ? kb / 1024.0 : 0.0;
}

std::string CheckMemory(double needMb, double budgetMb, const std::string& what) {
  const double budget = budgetMb > 0 ? budgetMb : 0.8 * AvailableMemoryMb();
  if (!(budget > 0) || needMb <= budget) return {};
  auto size = [](double mb) {
    char buf[32];
    if (mb >= 1024) std::snprintf(buf, sizeof buf, "%.1f GB", mb / 1024.0);
    else std::snprintf(buf, sizeof buf, "%.0f MB", std::ceil(mb));
    return std::string(buf);
  };
  return what + " would need about " + size(needMb) + " of memory, more than the " + size(budget) +
         (budgetMb > 0 ? " allowed" : " available");
}

double ProcessPeakMemoryMb() {
  RememberProcessPeak(HighWaterMb());
  return g_processPeakMb.load();
}

}  // namespace vcgext
