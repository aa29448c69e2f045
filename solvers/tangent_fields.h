// Tangent-field recipes on a prepared surface (solvers/pipeline.h), with results on the input's
// vertices as 3D vectors: what `ifem field` (and the Python package) run. The fields themselves
// are direction_field.h's (smoothest / aligned n-direction fields on the connection Laplacian).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "solvers/pipeline.h"
#include "solvers/vector_heat.h"

namespace ifem::solvers {

/// A direction to hold at an input vertex, given in space: projected to the vertex's tangent
/// plane (solvers::tangent_basis_3d), one of the field's n directions points along it.
struct InputDirection {
  Index vertex = kInvalidIndex;        ///< input vertex id
  Eigen::Vector3d direction{1, 0, 0};  ///< any length; must not be normal to the surface
};

/// What direction_field_on() computes.
struct FieldSettings {
  int symmetry = 1;             ///< n: 1 vectors, 2 lines, 4 crosses
  bool align_boundary = false;  ///< hold the field along the boundary (manifold path only)
  std::vector<InputDirection> constraints;
};

/// A field on the input's vertices.
struct TangentFieldResult {
  Eigen::MatrixX3d vectors;  ///< #V_in×3 unit tangent vectors: one of the n directions (0: none)
  Eigen::VectorXd angle;     ///< #V_in: that direction's angle in the vertex's coordinate
  /// #V_in: indices (units of 1/n) of the singular faces of the intrinsic triangulation, each
  /// added to its corner of lowest id (an input vertex whenever the face has one).
  Eigen::VectorXd singularity;
  Index singular_faces = 0;  ///< faces with a nonzero index
  long total_index = 0;      ///< Σ indices over all faces (n·χ on a closed surface)
  Index constrained = 0;     ///< vertices held (constraints and boundary)
  double energy = 0.0;       ///< the field's Dirichlet energy per unit mass (0: parallel)
  int iterations = 0;        ///< LOBPCG steps (0: every component constrained)
};

/// The smoothest n-direction field on s (intrinsic Delaunay, refined or not), through the given
/// directions and, when asked, along the boundary; components without any constraint get
/// their globally smoothest field.
/// @throws InvalidInput on bad settings, a vertex out of [0, #V_in), a direction normal to the
///         surface there, or a surface that did not take the manifold path (the tufted cover and
///         point clouds: their vertices have several fans, so directions are not the surface's)
TangentFieldResult direction_field_on(const PreparedSurface& s, const FieldSettings& settings);

/// The Vector Heat Method solver for s (VectorHeatSolver on s.tri, already intrinsic Delaunay,
/// with the heat step of distance_options(s) and the input's boundary), for transport_on() and
/// log_map_on().
/// @throws InvalidInput if s did not take the manifold path (as direction_field_on())
VectorHeatSolver vector_heat_solver(const PreparedSurface& s);

/// Parallel transport of a 3D vector given at input vertex `source` (projected to its tangent
/// plane, keeping its length) to every input vertex, as 3D tangent vectors (#V_in×3; 0 where no
/// source reaches). Meaningful on the manifold path (fem/connection.h).
/// @throws InvalidInput on a source out of range or a vector normal to the surface there
Eigen::MatrixX3d transport_on(const PreparedSurface& s, const VectorHeatSolver& solver,
                              Index source, const Eigen::Vector3d& vector,
                              VectorHeatReport* report = nullptr);

/// The logarithmic map about input vertex `source`: per input vertex (#V_in×2) its Riemannian
/// coordinates (u, v) = d·(cos θ, sin θ), d the geodesic distance and θ the direction in which
/// the geodesic leaves the source, counter-clockwise (with the faces' orientation) from the
/// source's reference direction, basis e1 of tangent_basis_3d() at the source (the direction
/// of its first edge). (0, 0) at the source.
/// @throws InvalidInput on a source out of range or unreferenced
Eigen::MatrixX2d log_map_on(const PreparedSurface& s, const VectorHeatSolver& solver, Index source,
                            VectorHeatReport* report = nullptr);

}  // namespace ifem::solvers
