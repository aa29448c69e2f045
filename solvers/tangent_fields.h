// Tangent-field recipes on a prepared surface (solvers/pipeline.h), with results on the input's
// vertices as 3D vectors: what `ifem field` (and the Python package) run. The fields themselves
// are direction_field.h's (smoothest / aligned n-direction fields on the connection Laplacian).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "solvers/pipeline.h"

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
};

/// The smoothest n-direction field on s (intrinsic Delaunay, refined or not), through the given
/// directions and, when asked, along the boundary; components without any constraint get
/// their globally smoothest field.
/// @throws InvalidInput on bad settings, a vertex out of [0, #V_in), a direction normal to the
///         surface there, or align_boundary on a surface whose triangulation has no boundary of
///         its own (the tufted cover, point clouds)
TangentFieldResult direction_field_on(const PreparedSurface& s, const FieldSettings& settings);

}  // namespace ifem::solvers
