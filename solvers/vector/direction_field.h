// Smoothest n-direction fields on an intrinsic triangulation (Knöppel, Crane, Pinkall,
// Schröder, "Globally Optimal Direction Fields", SIGGRAPH 2013), with the connection Laplacian
// of fem/connection.h: the globally smoothest field, fields aligned to fixed directions (given
// vertices, the boundary), and the singularities of a field.
//
// An n-direction field (n = 1 vectors, 2 lines, 4 crosses) is stored in its power
// representation: one complex number u_v per vertex, in v's angular coordinate
// (fem::TangentFrames); the n directions at v are arg(u_v)/n + 2πk/n. A vertex with u_v = 0
// (unreferenced, or a field that vanished there) has no direction. The solvers also run on a
// connection Laplacian given as an operator (the frame path of fem/frame_connection.h, where the
// coordinate is a per-vertex 3D frame): the triangulation versions build L_n and M and call
// those.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "fem/connection.h"
#include "intrinsic/core/triangulation.h"
#include "solvers/scalar/components.h"
#include "solvers/vector/tangent_basis.h"

namespace ifem::solvers {

/// A direction to hold: at vertex `vertex`, one of the n directions is `angle` (radians, in
/// the vertex's angular coordinate: 0 along tri.vertex_halfedge(vertex), counter-clockwise).
struct DirectionConstraint {
  Index vertex = kInvalidIndex;
  double angle = 0.0;
};

/// Options of the direction-field solvers.
struct DirectionFieldOptions {
  int symmetry = 1;         ///< n ≥ 1
  int max_iterations = 30;  ///< LOBPCG steps for the smoothest field, ≥ 1
  /// Stop when the Rayleigh quotient changes by less than this, relative; > 0.
  double tolerance = 1e-6;
  /// @throws InvalidInput naming the field
  void validate() const;
};

/// A field and what computing it found.
struct DirectionField {
  Eigen::VectorXcd u;     ///< #V power representation, |u_v| = 1 (0 where undefined)
  double energy = 0.0;    ///< uᴴ L_n u / uᴴ M u of the field before normalization per vertex
  int iterations = 0;     ///< LOBPCG steps (smoothest field)
  Index constrained = 0;  ///< vertices held by constraints
  Index free_components = 0;  ///< components without a constraint: their smoothest field
  /// Components without a field (u = 0 on them, "no direction"): no vertex of positive mass
  /// (a caller excludes a component by labelling its vertices kInvalidIndex while keeping
  /// Components::count), or a non-finite entry of the mass or of L_n on their rows. Counted, not
  /// an error; constraints on them are ignored.
  Index empty_components = 0;
};

/// The globally smoothest n-direction field: the eigenvector of L_n u = λ M u with the smallest
/// λ (LOBPCG preconditioned by a complex Cholesky factor of L_n + εM: one solve per step, as
/// inverse iteration, converging in far fewer steps), normalized per vertex. On a
/// flat torus λ = 0 (a parallel field); on a sphere λ > 0 and the field has singularities.
/// Each connected component gets its own smoothest field (shifted on its own scale: pieces of
/// very different sizes, as in a triangle soup, converge alike), except the empty ones
/// (DirectionField::empty_components).
/// @throws InvalidInput on bad options; SolverError if a factorization fails
DirectionField smoothest_field(const intrinsic::IntrinsicTriangulation& tri,
                               const fem::TangentFrames& frames,
                               const DirectionFieldOptions& options = {});

/// smoothest_field() on operators: L_n a #V×#V Hermitian PSD connection Laplacian of symmetry
/// n = options.symmetry (e.g. fem::connection_laplacian_from_frames), mass the #V lumped mass
/// that goes with it (0 on unreferenced vertices), comps its connected components.
/// @throws InvalidInput on bad options or sizes; SolverError if a factorization fails
DirectionField smoothest_field(const fem::ComplexSparseMatrix& L_n, const Eigen::VectorXd& mass,
                               const Components& comps, const DirectionFieldOptions& options = {});

/// The smoothest n-direction field through the given directions: u held at e^{i n angle} on
/// constrained vertices, L_n u = 0 elsewhere (harmonic interpolation with the connection),
/// normalized per vertex; components without any constraint take the smoothest field.
/// Several constraints on one vertex: the mean of their powers (counted in `constrained` once).
/// @throws InvalidInput on a vertex out of range, a non-finite angle or bad options
DirectionField aligned_field(const intrinsic::IntrinsicTriangulation& tri,
                             const fem::TangentFrames& frames,
                             const std::vector<DirectionConstraint>& constraints,
                             const DirectionFieldOptions& options = {});

/// aligned_field() on operators (as the operator form of smoothest_field()); angles in the
/// coordinates of L_n.
DirectionField aligned_field(const fem::ComplexSparseMatrix& L_n, const Eigen::VectorXd& mass,
                             const Components& comps,
                             const std::vector<DirectionConstraint>& constraints,
                             const DirectionFieldOptions& options = {});

/// One constraint per boundary vertex: along its boundary, for n-direction fields (n =
/// symmetry). The boundary's two tangents at v, the outgoing boundary edge (angle a) and the
/// incoming one continued through v (angle b, the direction to the previous vertex plus π),
/// agree as n-directions when n (b − a) is a multiple of 2π (a straight boundary for every n;
/// a corner of angle π/2 or 3π/2 for n = 4); otherwise the constraint is their n-direction
/// mean, the angle whose n-th multiple bisects the shorter arc from n a to n b (a tie, an arc
/// of π, goes counter-clockwise from n a). So a cross field is along both sides of a square's
/// or an L's corners, and a vector field takes the bisector of the two tangents (on a smooth
/// boundary, the tangent to second order). Empty on a triangulation without boundary (e.g. a
/// tufted cover). Angles in frames' coordinates (docs/decisions.md D-097).
/// @throws InvalidInput if symmetry < 1 or the frames are not tri's
std::vector<DirectionConstraint> boundary_constraints(const intrinsic::IntrinsicTriangulation& tri,
                                                      const fem::TangentFrames& frames,
                                                      int symmetry = 1);

/// The index of the field around each face, in units of 1/n (#F integers; a vector field's
/// index is ×1, a cross field's in quarter turns): the field's turning along the face's three
/// sides, relative to parallel transport, plus n times the face's share of curvature. On a
/// closed surface the indices sum to n·χ (Poincaré–Hopf: 2n on a sphere, 0 on a torus).
/// Faces touching a vertex without a direction get 0.
Eigen::VectorXi face_indices(const intrinsic::IntrinsicTriangulation& tri,
                             const fem::TangentFrames& frames, const Eigen::VectorXcd& u,
                             int symmetry);

/// The index of a field on the frame path around each of the given triangles (input faces:
/// #T integers, units of 1/n), as face_indices(): the field's turning along the three sides
/// relative to the frame transport (fem::frame_transport), plus n times the face's holonomy
/// arg(r_ab r_bc r_ca), the triangle traversed counter-clockwise about its corners' normals
/// (reversed where (b − a) × (c − a) points against n_a + n_b + n_c). On a closed, orientable
/// surface with fine faces they sum to n·χ. Triangles touching a vertex without a direction get 0.
/// @param u #V ≥ #V_in power representation in the frames of basis
/// @throws InvalidInput if a triangle index is out of range of the basis or u
Eigen::VectorXi frame_face_indices(const Positions& positions,
                                   const std::vector<Triangle>& triangles,
                                   const TangentBasis3d& basis, const Eigen::VectorXcd& u,
                                   int symmetry);

}  // namespace ifem::solvers
