// Per-vertex 3D tangent bases: how tangent vectors, complex numbers per vertex, are placed in
// space. Two kinds: tangent_basis_3d() places the intrinsic angular coordinates of
// fem/connection.h (the manifold path), frame_basis_3d() makes consistently oriented frames from
// normals for the frame path of fem/frame_connection.h (tufted covers, point clouds).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "fem/connection.h"
#include "intrinsic/core/triangulation.h"
#include "intrinsic/core/types.h"
#include "intrinsic/integer/correspondence.h"
#include "intrinsic/io/mesh_io.h"

namespace ifem::solvers {

/// Per-vertex 3D tangent bases that place the intrinsic angular coordinates in space.
struct TangentBasis3d {
  Eigen::MatrixX3d normal;  ///< #V_in×3 unit normal (sign: the faces' counter-clockwise side)
  Eigen::MatrixX3d e1;      ///< #V_in×3 unit, ⟂ normal: the direction of angle 0
  Eigen::MatrixX3d e2;      ///< #V_in×3 normal × e1: the direction of angle π/2
  /// Vertices whose basis is a fallback: no outgoing halfedge with a known direction (without
  /// signposts: no intrinsic neighbour with a position; e1 is then an arbitrary tangent
  /// direction), or no usable normal (a degenerate neighbourhood: normal z).
  Index fallback_vertices = 0;
  /// frame_basis_3d(): neighbour pairs whose oriented normals disagree (n_i·n_j < 0).
  Index orientation_conflicts = 0;
};

/// 3D tangent bases of the first #V_in = positions.rows() vertices of tri (the input's vertices
/// on every path of solvers::prepare_surface).
///  - normal: the area-weighted normal of the input triangles around the vertex; without
///    triangles (a point cloud) the given normals (#V_in×3), else the smallest principal axis
///    of the vertex and its intrinsic neighbours. Its sign is then chosen so that the intrinsic
///    fan turns counter-clockwise about it (a vote over the outgoing halfedges), which makes it
///    agree with the angular coordinates even where the input's faces were reoriented.
///  - e1: the direction in which the vertex's reference halfedge (tri.vertex_halfedge(v))
///    leaves it, projected to the tangent plane. With a correspondence (tri refined or flipped
///    with signposts or integer coordinates) that is the halfedge's exact 3D direction on the
///    input surface (CorrespondenceView::halfedge_direction_3d(): the direction in the input
///    face it starts in, from the signpost or from the integers), known for every halfedge,
///    inserted heads included; both give the same basis to rounding. Without, it is the
///    chord towards the head's position; when the head is an inserted vertex (no position),
///    the first outgoing halfedge with an input head, rotated back by its angle.
/// @param frames tangent_frames(tri)
/// @param correspondence when tri has inserted vertices, the signposts or integer coordinates
///        it comes from (tri is its intrinsic(), possibly with all lengths scaled): without one
///        an input vertex whose intrinsic neighbours are all inserted gets an arbitrary e1 (a
///        fallback)
/// @throws InvalidInput on size mismatches (positions rows > #V, normals neither empty nor
///         #V_in×3, a triangle index out of range), or a correspondence whose triangulation
///         is not tri's (other vertex or halfedge counts or tails, or #V_in input vertices)
TangentBasis3d tangent_basis_3d(const Positions& positions, const std::vector<Triangle>& triangles,
                                const Eigen::MatrixX3d& normals,
                                const intrinsic::IntrinsicTriangulation& tri,
                                const fem::TangentFrames& frames,
                                std::optional<intrinsic::CorrespondenceView> correspondence = {});

/// tangent_basis_3d() of an input as read (its positions, triangles and, for point clouds,
/// normals).
TangentBasis3d tangent_basis_3d(const io::SurfaceInput& input,
                                const intrinsic::IntrinsicTriangulation& tri,
                                const fem::TangentFrames& frames,
                                std::optional<intrinsic::CorrespondenceView> correspondence = {});

/// Per-vertex 3D frames for the frame path (fem/frame_connection.h: the tufted cover of a
/// nonmanifold mesh, point clouds), where tangent vectors are x·e1 + y·e2 in space rather than
/// intrinsic angles. For the first #V_in = positions.rows() vertices of tri:
///  - normal, unoriented first: the area-weighted normal of the input triangles around the
///    vertex, or where those cancel (|Σ| < 0.2·Σ|n_f|: a nonmanifold vertex, reoriented faces)
///    the smallest principal axis of the vertex and its neighbours (the other ends of its edges
///    in tri); without triangles (a point cloud) the given normals (#V_in×3) where finite and
///    nonzero, else that principal axis. (The 1-ring of the point-cloud triangulation, not the
///    k nearest points, which smooth a coarse cloud's normals too much: docs/decisions.md D-036.)
///  - orientation (Hoppe et al. 1992): per connected component of the neighbour graph, a
///    minimum spanning tree with weights 1 − |n_i·n_j| from the component's lowest vertex,
///    each child flipped to agree with its parent; then the component's sign that agrees with
///    most of the faces' (or the given normals') signs, or, where nothing gives a sign (PCA
///    only), that points away from the component's centroid. A mesh keeps its faces'
///    orientation where that has no more disagreeing edges than the propagation.
///  - e1: the x axis projected to the tangent plane (the y axis where |n_x| ≥ 0.9), e2 = n × e1.
/// orientation_conflicts counts the neighbour pairs with n_i·n_j < 0 afterwards: nonzero on
/// non-orientable inputs (a Möbius strip), and at sharp creases and thin sheets where an edge
/// joins the two sides.
/// @throws InvalidInput on size mismatches (positions rows > #V, normals neither empty nor
///         #V_in×3, a triangle index out of range), non-finite positions
TangentBasis3d frame_basis_3d(const Positions& positions, const std::vector<Triangle>& triangles,
                              const Eigen::MatrixX3d& normals,
                              const intrinsic::IntrinsicTriangulation& tri);

/// frame_basis_3d() of an input as read.
TangentBasis3d frame_basis_3d(const io::SurfaceInput& input,
                              const intrinsic::IntrinsicTriangulation& tri);

/// 3D tangent vectors of the first basis.e1.rows() entries of z: Re z·e1 + Im z·e2, #V_in×3.
///
/// Approximation: the angular coordinate is read as the angle in the tangent plane. This is
/// exact where the vertex's fan is flat (angle sum 2π) and its intrinsic edges point along the
/// projected chords (edges of a planar neighbourhood). At a cone vertex the rescaling spreads
/// the angle defect 2π − Θ_v over all directions, so a direction is off by at most about
/// |2π − Θ_v|/2 (O(h²·K), K the Gaussian curvature, on a fine smooth mesh), plus, without
/// signposts, the chord projection's error of O(h·κ) for a flipped (non-input) reference edge. On
/// vertices with several fans (nonmanifold vertices, tufted covers, point clouds) the coordinate
/// runs through all fans one after the other (fem/connection.h), so only directions in the
/// reference fan map right.
/// @throws InvalidInput if z has fewer entries than the basis
Eigen::MatrixX3d to_3d(const Eigen::VectorXcd& z, const TangentBasis3d& basis);

}  // namespace ifem::solvers
