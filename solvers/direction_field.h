// Smoothest n-direction fields on an intrinsic triangulation (Knöppel, Crane, Pinkall,
// Schröder, "Globally Optimal Direction Fields", SIGGRAPH 2013), with the connection Laplacian
// of fem/connection.h: the globally smoothest field, fields aligned to fixed directions (given
// vertices, the boundary), and the singularities of a field.
//
// An n-direction field (n = 1 vectors, 2 lines, 4 crosses) is stored in its power
// representation: one complex number u_v per vertex, in v's angular coordinate
// (fem::TangentFrames); the n directions at v are arg(u_v)/n + 2πk/n. A vertex with u_v = 0
// (unreferenced, or a field that vanished there) has no direction.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "fem/connection.h"
#include "intrinsic/core/triangulation.h"

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
};

/// The globally smoothest n-direction field: the eigenvector of L_n u = λ M u with the smallest
/// λ (LOBPCG preconditioned by a complex Cholesky factor of L_n + εM: one solve per step, as
/// inverse iteration, converging in far fewer steps), normalized per vertex. On a
/// flat torus λ = 0 (a parallel field); on a sphere λ > 0 and the field has singularities.
/// Each connected component gets its own smoothest field.
/// @throws InvalidInput on bad options; SolverError if a factorization fails
DirectionField smoothest_field(const intrinsic::IntrinsicTriangulation& tri,
                               const fem::TangentFrames& frames,
                               const DirectionFieldOptions& options = {});

/// The smoothest n-direction field through the given directions: u held at e^{i n angle} on
/// constrained vertices, L_n u = 0 elsewhere (harmonic interpolation with the connection),
/// normalized per vertex; components without any constraint take the smoothest field.
/// Several constraints on one vertex: the mean of their powers (counted in `constrained` once).
/// @throws InvalidInput on a vertex out of range, a non-finite angle or bad options
DirectionField aligned_field(const intrinsic::IntrinsicTriangulation& tri,
                             const fem::TangentFrames& frames,
                             const std::vector<DirectionConstraint>& constraints,
                             const DirectionFieldOptions& options = {});

/// One constraint per boundary vertex: along its boundary (the direction of its outgoing
/// boundary halfedge). Empty on a triangulation without boundary (e.g. a tufted cover).
std::vector<DirectionConstraint> boundary_constraints(const intrinsic::IntrinsicTriangulation& tri,
                                                      const fem::TangentFrames& frames);

/// The index of the field around each face, in units of 1/n (#F integers; a vector field's
/// index is ×1, a cross field's in quarter turns): the field's turning along the face's three
/// sides, relative to parallel transport, plus n times the face's share of curvature. On a
/// closed surface the indices sum to n·χ (Poincaré–Hopf: 2n on a sphere, 0 on a torus).
/// Faces touching a vertex without a direction get 0.
Eigen::VectorXi face_indices(const intrinsic::IntrinsicTriangulation& tri,
                             const fem::TangentFrames& frames, const Eigen::VectorXcd& u,
                             int symmetry);

}  // namespace ifem::solvers
