// Direction fields aligned to curves (thesis proposal Fig. 10 left: a cross field conforming to
// curves on a scan). The curves are inserted into the intrinsic triangulation exactly as for
// data on curves (solvers/recipes/curves.h: FlipOut geodesics, Bézier curves, constrained Delaunay
// flips, optional constrained refinement), so every curve is a chain of edges; the field is then
// held along the curve at every vertex on it and is the smoothest field elsewhere
// (solvers::aligned_field on the constrained triangulation):
//
//   input mesh + curves ──► prepare_curve_surface()            (solvers/recipes/curves.h)
//                       ──► curve_constraints(): the curve's direction at each of its vertices
//                       ──► curve_direction_field(): aligned_field with them, the boundary and
//                           the given directions ──► results on the input's vertices
//
// A curve edge joins two held vertices, so it never enters the linear system: a curve edge
// left non-Delaunay (negative cotan weight, which constrained triangulations allow) cannot make
// the system indefinite.
#pragma once

#include <vector>

#include "fem/connection.h"
#include "intrinsic/geodesic/curve_network.h"
#include "solvers/recipes/curves.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/vector/direction_field.h"

namespace ifem::solvers {

/// The curves' directions at their vertices, in the angular coordinates of `frames` (of tri, the
/// triangulation the network lives in): at each vertex of each curve, the direction of the curve
/// edge leaving it (towards the next vertex along the curve) and the continuation of the edge
/// arriving (the direction pointing away from the previous vertex), one constraint each. A
/// vertex inside a curve thus gets two, an end of an open curve one; aligned_field() holds the
/// mean of their n-th powers: for n = 1 a vector pointing along the curve's direction of travel
/// (its vertex order), for even n an unsigned line / cross. On a flat surface that mean is
/// exactly tangent to a circle through equally spaced vertices. Vertices where several curves
/// meet take the mean over all of them (crossing curves agree for n = 4 when perpendicular).
/// @throws InvalidInput if the frames or the network are not tri's (sizes)
std::vector<DirectionConstraint> curve_constraints(const intrinsic::IntrinsicTriangulation& tri,
                                                   const intrinsic::CurveNetwork& network,
                                                   const fem::TangentFrames& frames);

/// The smoothest n-direction field on s.surface.tri held along the curves (curve_constraints())
/// and as `settings` asks (the boundary, directions at input vertices, intrinsic constraints),
/// with results on the input's vertices (direction_field_on()). The curves' values, if any, are
/// not used; a slit is an ordinary curve here (the field is not cut).
/// @throws InvalidInput as direction_field_on()
TangentFieldResult curve_direction_field(const CurveSurface& s, const FieldOptions& settings);

}  // namespace ifem::solvers
