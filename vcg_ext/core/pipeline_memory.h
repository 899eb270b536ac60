#pragma once
/// \file pipeline_memory.h
/// The memory each filter of the quad pipeline needs beyond what its host (MeshLab) already
/// holds, from the input's triangle count, and the refusal of an input that would not fit: the
/// kernel would otherwise kill the process, MeshLab with it and the user's unsaved work
/// (docs/robustness.md "Scans too large for the memory"). The estimates are fitted to what was measured on bunny00 and
/// its midpoint refinements up to 4.8 M triangles (pipeline_memory.cpp).
#include <string>

namespace vcgext {

/// The quad pipeline's filters (paper §3.1 Fitmaps, §3.3 simplification, §3.4–3.5 fit and
/// displacement).
enum class PipelineStep { Fitmaps, Simplification, FitAndBake };

/// Memory (MB) `step` needs beyond its input on an input of `triangles` triangles, at the
/// filters' default parameters: a line above what was measured (at 4.8 M triangles +7 … +18 %,
/// more on small inputs, whose needs are small).
double EstimatePipelineMemoryMb(PipelineStep step, double triangles);

/// "" when `step` on `triangles` triangles fits the budget (CheckMemory: `budgetMb`, or when 0,
/// 80 % of the memory available now), else "a [reference] layer of N triangles would need about
/// X of memory, more than …" and what to do: decimate the layer first (a scan of a few million
/// triangles gives the same cage) or free memory. The caller names its filter.
std::string CheckPipelineMemory(PipelineStep step, double triangles, double budgetMb);

}  // namespace vcgext
