// The common subdivision from integer coordinates: the overlay of the intrinsic and the input
// triangulations, with its combinatorics read from the normal coordinates and roundabouts
// (docs/decisions.md D-193).
#pragma once

#include <vector>

#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/refine/common_subdivision.h"

namespace ifem::intrinsic {

/// The common subdivision of nc, in the format of common_subdivision(SignpostTriangulation):
/// vertices are input vertices (same ids), then inserted intrinsic vertices (same ids as in
/// nc.intrinsic()), then the crossings of every intrinsic edge (edge by edge, in the order of
/// trace_edge()); each polygon (one intrinsic face ∩ one input face, bounded by arcs of input
/// edges and pieces of intrinsic sides) is split into a fan of triangles recording both faces
/// (input_face as an index into the faces given). Which input face a polygon lies in comes from
/// the integers (the side of an input edge an arc leaves it on; across uncrossed sides, the
/// neighbour's); positions come from the traced crossings (positions along input edges), and an
/// inserted vertex's position from a rigid map of the layout of a polygon it is a corner of,
/// fixed by two known points: onto the input face's 3D plane where the face's intrinsic lengths
/// are its 3D ones, else onto the face's intrinsic layout, read as barycentric coordinates
/// (clamped to the face) of the 3D triangle. So the triangles in each input face tile its 3D
/// triangle, mollified or not.
/// @throws InvalidInput if the coordinates are inconsistent, or an inserted vertex cannot be
///         placed (no polygon around it has two known points)
CommonSubdivision common_subdivision(const NormalCoordinateTriangulation& nc);

/// Where every intrinsic vertex of nc lies on the input (a face of nc.input() and barycentric
/// coordinates, as SignpostTriangulation::vertex_location): input vertices at a corner of a
/// face, vertices on an input edge on that edge's side, vertices inside faces as
/// common_subdivision() places them, with barycentric coordinates taken in the input face's
/// intrinsic layout (so the call builds it when there are such vertices: O(size of the
/// overlay)). Unreferenced vertices get the default SurfacePoint.
/// @throws InvalidInput as common_subdivision()
std::vector<SurfacePoint> vertex_locations(const NormalCoordinateTriangulation& nc);

}  // namespace ifem::intrinsic
