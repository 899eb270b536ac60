#pragma once
/// \file osd_refiner.h
/// Internal to vcg_ext/subdiv: the one place where a control mesh and LimitSurfaceOptions become
/// OpenSubdiv's topology refiner (scheme, boundary rule, sharp creases and corners), so that the
/// limit surface and the subdivided cage (subdivide_once.h) follow the same rules.
#include <opensubdiv/far/topologyRefiner.h>

#include <memory>
#include <vector>

#include "vcg_ext/subdiv/limit_surface.h"

namespace vcgext::subdiv_detail {

/// OpenSubdiv's topology refiner of the control mesh (faces as sizes + flat vertex lists) with
/// the options' scheme, boundary rule and infinitely sharp crease edges and corners; null when
/// OpenSubdiv rejects the topology. Unrefined.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> CreateRefiner(int nV, const std::vector<int>& sizes,
                                                                const std::vector<int>& verts,
                                                                const LimitSurfaceOptions& opt);

}  // namespace vcgext::subdiv_detail
