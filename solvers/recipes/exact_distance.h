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

/// The points of a path on tri (SurfacePoints, e.g. intrinsic::ExactDistance::path_to_source())
/// in 3D: each the blend, by its barycentric coordinates, of position_of(v) at its face's
/// corners v (a zero coordinate's corner is not read). position_of: Index → Eigen::Vector3d.
template <class PositionOf>
std::vector<Eigen::Vector3d> path_points_3d(const intrinsic::IntrinsicTriangulation& tri,
                                            const std::vector<intrinsic::SurfacePoint>& path,
                                            const PositionOf& position_of) {
  std::vector<Eigen::Vector3d> line;
  line.reserve(path.size());
  for (const intrinsic::SurfacePoint& p : path) {
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      if (p.bary[k] != 0.0) q += p.bary[k] * position_of(tri.tail(3 * p.face + k));
    }
    line.push_back(q);
  }
  return line;
}

/// The exact geodesics back from input vertices `from` to their nearest source, as 3D polylines
/// (each from the vertex to the source; a vertex that is a source gives one point, an
/// unreachable one an empty polyline), placed on the input's own faces.
/// @param full exact_distance()'s full result on s.tri
/// @pre s was prepared without flips and without refinement (PrepareOptions::intrinsic_delaunay
///      false, no refine): then every face corner of s.tri is an input vertex and the paths'
///      points have positions on the input
/// @throws InvalidInput if s was flipped or refined, or an id of `from` is not in [0, #V_in)
std::vector<std::vector<Eigen::Vector3d>> exact_paths_3d(const PreparedSurface& s,
                                                         const intrinsic::ExactDistance& full,
                                                         const std::vector<Index>& from);

}  // namespace ifem::solvers
