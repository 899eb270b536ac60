#pragma once
/// \file memory.h
/// Peak resident memory per stage (issue 12: "report peak memory per stage"). Linux keeps one
/// high-water mark per process (VmHWM); writing "5" to /proc/self/clear_refs resets it, so the
/// peak of a stage is the mark read at its end after a reset at its start. The whole-process
/// peak is remembered here across resets (getrusage's ru_maxrss is reset with the mark).
/// Elsewhere, or where the reset is not allowed, every stage reports the process peak so far.
#include <string>
#include <utility>
#include <vector>

namespace vcgext {

/// Peak resident memory (MB) since the last StagePeakMemoryMb() call (or process start), and
/// starts a new stage. Not thread-safe with respect to other stage bookkeeping: call it from
/// the thread that runs the stages.
double StagePeakMemoryMb();

/// Largest resident memory (MB) the process has had, across all stages.
double ProcessPeakMemoryMb();

/// Resident memory (MB) of the process now (VmRSS of /proc/self/status); 0 where it cannot be read.
double ResidentMemoryMb();

/// Memory (MB) the kernel could give this process now without swapping (MemAvailable of
/// /proc/meminfo); 0 where it cannot be read. Used to refuse work that would exhaust the machine
/// (FitParams::maxMemoryMb) with an error instead of being killed by the kernel.
double AvailableMemoryMb();

/// "" when `needMb` fits the budget — `budgetMb`, or when that is 0, 80 % of AvailableMemoryMb()
/// (nothing is refused where that cannot be read), lowered to the environment variable
/// FITMAP_MAX_MEMORY_MB (MB) where that is set (a shared machine's limit; how the tests make a
/// filter refuse) — else "<what> would need about X of memory, more than the Y allowed /
/// available". Work that would exhaust the machine is refused with it before it starts: the
/// kernel would otherwise kill the process (MeshLab with it).
std::string CheckMemory(double needMb, double budgetMb, const std::string& what);

/// Per stage: name and peak resident memory in MB.
using StageMemory = std::vector<std::pair<std::string, double>>;

}  // namespace vcgext
