// Signed distance to curves and oriented points (the signed heat method, solvers/vector/
// signed_heat.h) on the prepared surfaces of the other recipes, results on the input's vertices:
//
//   input mesh + curves  ──► prepare_curve_surface() (curves as constrained edges, curves.h)
//                        ──► signed_distance(CurveSurface): on a copy of its triangulation, curve
//                            edges split into pieces of at most h (FlipOut leaves long ones) and
//                            flipped to constrained Delaunay; normals of the pieces; intrinsic
//                            path (an edge-manifold, orientable mesh)
//   input (mesh, tufted cover, point cloud) + oriented points (an input vertex and a 3D normal)
//                        ──► prepare_surface()  (pipeline.h)
//                        ──► signed_distance(PreparedSurface, points): the frame path
//
// Side convention for curves: seen from the side the faces' normals point to, walking along the
// curve (from its first vertex to its second), the right-hand side is positive, the left-hand
// side negative; so a counter-clockwise loop has negative values inside. For oriented points the
// side the normals point to is positive.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "solvers/recipes/curves.h"
#include "solvers/recipes/pipeline.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/vector/signed_heat.h"

namespace ifem::solvers {

/// Options of signed_distance().
struct SignedDistanceOptions {
  /// m in t = m·h², h the input's mean side length (as the heat distance); > 0, finite.
  double time_factor = 1.0;
  SignedLevelSet level_set = SignedLevelSet::kZeroSet;
  /// @throws InvalidInput naming the field
  void validate() const;
};

/// What signed_distance() did (SignedHeatReport, on the prepared triangulation).
using SignedDistanceReport = SignedHeatReport;

/// Signed distance to the curves of s (every curve counts, its values and slits ignored), #V_in
/// in the input's order: 0 on the curves' vertices (kZeroSet), the side by the convention above.
/// Curves may be open, broken into pieces, or have gaps: the diffused normals fill in. h: the
/// input's (distance_options(s.surface)), the split length and the heat step's.
/// @throws InvalidInput on bad options; SolverError if a factorization fails
Eigen::VectorXd signed_distance(const CurveSurface& s, const SignedDistanceOptions& options = {},
                                SignedDistanceReport* report = nullptr);

/// Signed distance to oriented points: each an input vertex with a normal (any length, not normal
/// to the surface: its projection to the vertex's tangent plane is used). #V_in, NaN on vertices
/// of components without a point. Runs on the frame path on every kind of input (manifold,
/// tufted cover, point cloud), so s must not be refined.
/// @throws InvalidInput on no point, a vertex out of range, repeated or used by no face, a normal
///         that is zero, not finite or normal to the surface (naming its origin), a refined s,
///         bad options; SolverError if a factorization fails
Eigen::VectorXd signed_distance(const PreparedSurface& s, const std::vector<InputDirection>& points,
                                const SignedDistanceOptions& options = {},
                                SignedDistanceReport* report = nullptr);

}  // namespace ifem::solvers
