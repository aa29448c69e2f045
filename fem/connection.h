// Tangent spaces of an intrinsic triangulation and the connection Laplacian (Sharp, Soliman,
// Crane, "The Vector Heat Method", ACM TOG 2019; Knöppel, Crane, Pinkall, Schröder, "Globally
// Optimal Direction Fields", SIGGRAPH 2013), from edge lengths alone.
//
// A tangent vector at vertex v is a complex number in v's angular coordinate: the outgoing
// halfedges around v are laid out counter-clockwise (with the faces' orientation) from a
// reference halfedge, tri.vertex_halfedge(v), at angle 0, with their corner angles scaled by
// angle_scale(v). An interior vertex's fan is rescaled to fill 2π: angle_scale = 2π / Θ_v, Θ_v
// the vertex angle sum. A boundary vertex keeps its true angles, angle_scale = 1, whenever they
// fit in one turn (Θ_v ≤ 2π): its fan spans [0, Θ_v] and the directions (Θ_v, 2π) point out of
// the surface. A boundary vertex with Θ_v > 2π is compressed to exactly one turn, angle_scale =
// 2π / Θ_v, its two boundary edges both at angle 0, as at the tip of a slit (Θ = 2π), where they
// coincide (docs/decisions.md D-096). On a boundary vertex the reference is the fan's outgoing
// boundary halfedge (what vertex_halfedge() holds; were it not, the first halfedge of its fan
// is used), so the incoming boundary edge points at angle_scale × Θ_v. Parallel transport along
// the edge of halfedge h (tail i → head j) is the unit complex number r_h that takes i's
// coordinate to j's: a vector at angle α at i, read at j, is at α + arg r_h. It keeps the
// (scaled) angle to the edge: the direction of h at i, θ_h, goes to the direction pointing away
// from i at j, θ_twin(h) + π, so r_h = exp(i(θ_twin(h) − θ_h + π)) and r_twin(h) = conj(r_h). A
// boundary edge has no twin: its direction at j is read in face(h) (θ_next(h) + scale_j × the
// corner angle of next(h)).
//
// With scaled angles each face carries holonomy (the rotation of a vector carried around its
// three sides) Σ_c (scale_c − 1) α_c over its corners c; the terms at v's corners sum to the
// angle defect 2π − Θ_v at an interior vertex, 0 at a boundary vertex with Θ_v ≤ 2π, 2π − Θ_v at
// one with Θ_v > 2π. So the connection of a flat domain (every interior Θ = 2π, every boundary
// Θ ≤ 2π: a square, an L-shape, an annulus) is trivial: transport is path independent and a
// parallel field is constant.
//
// Vertices with several fans (a pinched, nonmanifold vertex) have their fans laid out one after
// the other (the fan of vertex_halfedge(v) first, then in the order of their smallest halfedge
// id), each starting where the previous one ended, all with the one scale of v: a consistent
// coordinate for each fan, not a meaningful one across fans (nothing is). The tufted cover and
// point-cloud triangulations are handled the same way. Their vertices have two or more fans
// (a manifold vertex's cover has a front and a back fan, each spanning only π), so there L is a
// well-defined Hermitian operator, PSD once intrinsic Delaunay, but not the surface's
// connection: vector fields on point clouds need frames from the points' normals
// (fem/frame_connection.h, which the solvers use on those paths).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>

#include "intrinsic/core/triangulation.h"

namespace ifem::fem {

using ComplexSparseMatrix = Eigen::SparseMatrix<std::complex<double>, Eigen::ColMajor, int>;

/// Per-vertex angular coordinates and per-halfedge transport.
struct TangentFrames {
  Eigen::VectorXd angle_sum;       ///< #V: Θ_v, radians (0 for an unreferenced vertex)
  Eigen::VectorXd angle_scale;     ///< #V: 2π/Θ_v inside, 2π/max(Θ_v, 2π) on the boundary
                                   ///< (1 while Θ_v ≤ 2π), 0 unreferenced
  Eigen::VectorXd halfedge_angle;  ///< #H: direction of h at tail(h), radians, in [0, 2π)
  Eigen::VectorXcd transport;      ///< #H: r_h, |r_h| = 1, tail(h)'s coordinate → head(h)'s
  /// The holonomy of the discrete connection at vertex v, in (−π, π]: over the faces of v's fan
  /// (that of vertex_halfedge(v)), the angle a vector turns when transported around the face's
  /// three sides, arg(r_h r_next(h) r_prev(h)), less the share of the face's two other corners,
  /// (angle_scale − 1) × corner angle each. Equals (angle_scale − 1) × Θ_v modulo 2π: the angle
  /// defect 2π − Θ_v at an interior vertex, 0 at a boundary vertex with Θ_v ≤ 2π, 2π − Θ_v at
  /// one with Θ_v > 2π (a test and a check, not used by the solvers; meaningless at a pinched
  /// vertex). 0 for an unreferenced vertex.
  /// @throws InvalidInput if v is out of range or the frames are not tri's
  double holonomy_around(const intrinsic::IntrinsicTriangulation& tri, Index v) const;
};

/// The tangent frames of tri (any intrinsic triangulation: manifold, refined, tufted cover,
/// point cloud). O(#H). A referenced vertex whose angle sum is 0 (only degenerate faces) gets
/// scale 0: all its directions at angle 0.
TangentFrames tangent_frames(const intrinsic::IntrinsicTriangulation& tri);

/// Connection Laplacian for n-direction fields (n = 1 vectors, 2 lines, 4 crosses), #V×#V complex
/// Hermitian positive semi-definite: L_ii = Σ_j w_ij, L_ij = −w_ij · r_{j→i}^n summed over the
/// edges joining i ≠ j (r_{j→i} the transport along the halfedge j → i), with the cotan weights
/// w_ij of cotan_laplacian() (same division by the multiplicity). With the lumped mass of
/// lumped_mass() it discretizes the Bochner Laplacian ∇*∇ of n-symmetric fields. A self-edge
/// (both ends at v) contributes only to v's diagonal, w·|1 − r_h^n|² (its own holonomy), so that
/// x*Lx = Σ_edges w_ij |x_i − r_{j→i}^n x_j|² stays a sum of squares. Unreferenced vertices have
/// zero rows. PSD is guaranteed when every w_ij ≥ 0, as on an intrinsic Delaunay triangulation
/// (flip_to_delaunay() first): unlike the scalar cotan Laplacian, a negative weight on an edge
/// of a face with non-zero holonomy can make an eigenvalue negative.
/// @throws InvalidInput if symmetry < 1 or the frames are not tri's
/// @throws Error on a non-finite cotan weight (a zero-area face), as cotan_laplacian()
ComplexSparseMatrix connection_laplacian(const intrinsic::IntrinsicTriangulation& tri,
                                         const TangentFrames& frames, int symmetry = 1);

}  // namespace ifem::fem
