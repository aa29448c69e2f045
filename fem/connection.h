// Tangent spaces of an intrinsic triangulation and the connection Laplacian (Sharp, Soliman,
// Crane, "The Vector Heat Method", ACM TOG 2019; Knöppel, Crane, Pinkall, Schröder, "Globally
// Optimal Direction Fields", SIGGRAPH 2013), from edge lengths alone.
//
// A tangent vector at vertex v is a complex number in v's angular coordinate: the outgoing
// halfedges around v are laid out counter-clockwise (with the faces' orientation) from a
// reference halfedge, tri.vertex_halfedge(v), at angle 0, with their corner angles rescaled so
// that they fill 2π at an interior vertex (π at a boundary vertex, whose fan is a half-plane):
// angle_scale(v) = 2π / Θ_v, resp. π / Θ_v, Θ_v the vertex angle sum. Parallel transport along
// the edge of halfedge h (tail i → head j) is the unit complex number r_h that takes i's
// coordinate to j's: a vector at angle α at i, read at j, is at α + arg r_h.
//
// Vertices with several fans (a pinched, nonmanifold vertex) have their fans laid out one after
// the other in a fixed order, each starting where the previous one ended: a consistent
// coordinate for each fan, not a meaningful one across fans (nothing is). The tufted cover and
// point-cloud triangulations are handled the same way.
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
  Eigen::VectorXd angle_scale;     ///< #V: 2π/Θ_v inside, π/Θ_v on the boundary, 0 unreferenced
  Eigen::VectorXd halfedge_angle;  ///< #H: direction of h at tail(h), radians, in [0, 2π)
  Eigen::VectorXcd transport;      ///< #H: r_h, |r_h| = 1, tail(h)'s coordinate → head(h)'s
  /// The holonomy of the discrete connection around interior vertex v, in (−π, π]: the angle a
  /// vector turns when transported once around v's fan; equals the angle defect 2π − Θ_v modulo
  /// 2π (a test and a check, not used by the solvers).
  double holonomy_around(const intrinsic::IntrinsicTriangulation& tri, Index v) const;
};

/// The tangent frames of tri (any intrinsic triangulation: manifold, refined, tufted cover,
/// point cloud). O(#H).
TangentFrames tangent_frames(const intrinsic::IntrinsicTriangulation& tri);

/// Connection Laplacian for n-direction fields (n = 1 vectors, 2 lines, 4 crosses), #V×#V complex
/// Hermitian positive semi-definite: L_ii = Σ_j w_ij, L_ij = −w_ij · r_{j→i}^n summed over the
/// edges joining i ≠ j (r_{j→i} the transport along the halfedge j → i), with the cotan weights
/// w_ij of cotan_laplacian() (same division by the multiplicity). With the lumped mass of
/// lumped_mass() it discretizes the Bochner Laplacian ∇*∇ of n-symmetric fields. A self-edge
/// (both ends at v) contributes only to v's diagonal, through its own holonomy, so that L stays
/// Hermitian PSD. On an intrinsic Delaunay triangulation every weight w_ij is ≥ 0.
/// @throws InvalidInput if symmetry < 1
ComplexSparseMatrix connection_laplacian(const intrinsic::IntrinsicTriangulation& tri,
                                         const TangentFrames& frames, int symmetry = 1);

}  // namespace ifem::fem
