// Connected components of an intrinsic triangulation (through shared vertices of faces).
#pragma once

#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::solvers {

/// Vertex components: two vertices are in one component when a chain of faces joins them.
struct Components {
  std::vector<Index> label;  ///< #V: component id in [0, count), kInvalidIndex if unreferenced
  Index count = 0;           ///< number of components (unreferenced vertices not counted)
};

/// Labels the connected components (ids in order of their lowest vertex).
Components connected_components(const intrinsic::IntrinsicTriangulation& tri);

}  // namespace ifem::solvers
