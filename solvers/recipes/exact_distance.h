// Exact polyhedral geodesic distance through the pipeline: intrinsic::exact_distance() on a
// prepared surface (manifold, tufted cover, refined: the same surface, so the same distances),
// from input vertices, with results on the input's vertices in the input's order.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "intrinsic/geodesic/exact_distance.h"
#include "solvers/recipes/pipeline.h"

namespace ifem::solvers {

/// Exact geodesic distance from input vertices (ids < #V_in) to every input vertex (#V_in; +inf
/// where no source reaches, 0 at every source), on s.tri. On a mollified surface (s.mollify.delta
/// > 0) it is exact for the mollified lengths. Cost: see intrinsic::exact_distance().
/// @param[out] full optional: the whole result on s.tri (all its vertices, the paths back)
/// @throws InvalidInput on an empty source list, an id out of [0, #V_in) or a vertex in no face,
///         or when the windows exceed options.max_memory_bytes (the message gives the figures)
Eigen::VectorXd exact_distance(const PreparedSurface& s, const std::vector<Index>& sources,
                               const intrinsic::ExactDistanceOptions& options = {},
                               intrinsic::ExactDistance* full = nullptr);

}  // namespace ifem::solvers
