// Tangent-field recipes on a prepared surface (solvers/recipes/pipeline.h), with results on the
// input's vertices as 3D vectors: what `ifem field` (and the Python package) run. The fields
// themselves are direction_field.h's (smoothest / aligned n-direction fields on the connection
// Laplacian).
//
// Two paths, as the surface was prepared: the manifold path uses the intrinsic angular
// coordinates (fem/connection.h); the tufted path (nonmanifold / non-orientable meshes) and the
// point-cloud path use per-vertex 3D frames from the input's normals, oriented by propagation
// (frame_basis_3d(), fem/frame_connection.h), with the same scalar operators (L, M, heat
// distance) of the prepared triangulation. The frame path needs every vertex of the
// triangulation to be an input vertex (no refinement).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "solvers/recipes/pipeline.h"
#include "solvers/vector/direction_field.h"
#include "solvers/vector/vector_heat.h"

namespace ifem::solvers {

/// A direction to hold at an input vertex, given in space: projected to the vertex's tangent
/// plane (solvers::tangent_basis_3d), one of the field's n directions points along it.
struct InputDirection {
  Index vertex = kInvalidIndex;        ///< input vertex id
  Eigen::Vector3d direction{1, 0, 0};  ///< any length; must not be normal to the surface
  /// Where it was given, for messages ("FILE:line"); empty: named "direction K" by its index.
  std::string origin;
};

/// What direction_field_on() computes.
struct FieldOptions {
  int symmetry = 1;  ///< n: 1 vectors, 2 lines, 4 crosses
  /// Hold the field along the boundary: at each boundary vertex along the boundary edge leaving
  /// it (as the faces run); on the tufted path the input's boundary (edges of one input face).
  /// Not for point clouds (no boundary edges).
  bool align_boundary = false;
  /// Directions held at input vertices: one per vertex (the same direction given again is
  /// fine, a different one is refused naming both).
  std::vector<InputDirection> constraints;
  /// Directions given on the triangulation itself: at any vertex of s.tri (inserted ones too),
  /// angles in the coordinates of fem::tangent_frames(s.tri), e.g. curve_constraints() along
  /// curves (solvers/recipes/curve_fields.h). Held with the others (a vertex held several times
  /// takes the mean of the n-th powers). Manifold path only.
  std::vector<DirectionConstraint> intrinsic_constraints;
  /// @throws InvalidInput naming the field: symmetry < 1, an intrinsic constraint with a
  ///         negative vertex or a non-finite angle (the input directions are checked against
  ///         the surface by direction_field_on(), which knows #V and the tangent planes)
  void validate() const;
};

/// A field on the input's vertices.
struct TangentFieldResult {
  Eigen::MatrixX3d vectors;  ///< #V_in×3 unit tangent vectors: one of the n directions (0: none)
  Eigen::VectorXd angle;     ///< #V_in: that direction's angle in the vertex's coordinate
  /// #V_in: indices (units of 1/n) of the singular faces, each added to its corner of lowest id
  /// (an input vertex whenever the face has one): the faces of the intrinsic triangulation on
  /// the manifold path, the input's triangles on the frame path (frame_face_indices()); none
  /// for point clouds (no faces to turn around: all 0).
  Eigen::VectorXd singularity;
  /// #F_in (s.input.triangles, in order): the index (units of 1/n) around each input face
  /// (input_face_indices() on the manifold path, frame_face_indices() on the tufted path; empty
  /// for point clouds, and when unknown); sums to n·χ on a closed surface.
  Eigen::VectorXi face_singularity;
  Index singular_faces = 0;  ///< faces with a nonzero index
  long total_index = 0;      ///< Σ indices over all faces (n·χ on a closed surface)
  Index constrained = 0;     ///< vertices held (constraints and boundary)
  double energy = 0.0;       ///< the field's Dirichlet energy per unit mass (0: parallel)
  int iterations = 0;        ///< LOBPCG steps (0: every component constrained)
  /// Frame path: neighbour pairs whose oriented normals disagree (TangentBasis3d); 0 otherwise.
  Index orientation_conflicts = 0;
  /// Connected components of s.tri (a triangle soup: one per piece), and how they were treated:
  /// free_components took their own smoothest field (no constraint on them); empty_components
  /// have no field, vectors 0 and angle 0 on all their vertices ("no direction"): the flat ones
  /// (flat_components: no area in space, e.g. one zero-area face, so no tangent plane; given
  /// directions there are skipped, skipped_constraints) and those whose operators are not finite.
  Index components = 0;
  Index free_components = 0;
  Index empty_components = 0;
  Index flat_components = 0;
  Index skipped_constraints = 0;
};

/// The smoothest n-direction field on s (intrinsic Delaunay, refined or not), through the given
/// directions and, when asked, along the boundary; components without any constraint get
/// their globally smoothest field, each on its own (any number of components: a triangle soup
/// works), and components without area in space get none (TangentFieldResult::empty_components).
/// Its 3D vectors are in tangent_basis_3d()'s bases, with s.correspondence() when refined
/// (signposts or integer coordinates: right at every input vertex, those whose neighbours are
/// all inserted vertices included).
/// On the frame path (tufted, point cloud) the field lives in frame_basis_3d()'s frames.
/// @throws InvalidInput on bad settings, a vertex out of [0, #V_in), a direction normal to the
///         surface there, two different directions at one vertex (each named by its origin,
///         "FILE:line", or "direction K"), align_boundary on a point cloud, or a refined surface
///         off the manifold path (inserted vertices have no position for a frame)
TangentFieldResult direction_field_on(const PreparedSurface& s, const FieldOptions& settings);

/// The index of an n-direction field around each face of the input (s.input.triangles, in
/// order), in units of 1/n: solvers::face_indices() on the input triangulation, from the field
/// at the face's three corners and the transport along its three sides (geodesics of the same
/// surface, drawn in s.tri by the signposts: their directions at the corners in s.tri's
/// coordinates), plus n times the face's share of curvature. On a closed surface they sum to n·χ;
/// where s.tri is the input (no flips) they equal face_indices() on s.tri. Faces the build dropped
/// (a repeated vertex) get 0. The signposts are s.signposts, or, on the plain intrinsic Delaunay
/// path, rebuilt from the input with s's mollification and flips (O(#F) more work) and checked to
/// give back s.tri exactly; refined with integer coordinates (s.integer), the same directions
/// come from the integers (NormalCoordinateTriangulation::angle_from_input_halfedge()). Empty
/// when neither gives back s.tri, and off the manifold path.
/// @param frames fem::tangent_frames(s.tri); u the field on s.tri's vertices (power
///        representation, solvers/vector/direction_field.h)
/// @throws InvalidInput if u or frames do not have s.tri's vertex count
Eigen::VectorXi input_face_indices(const PreparedSurface& s, const fem::TangentFrames& frames,
                                   const Eigen::VectorXcd& u, int symmetry);

/// The Vector Heat Method solver for s (VectorHeatSolver on s.tri, already intrinsic Delaunay,
/// with the heat step of distance_options(s) and the input's boundary), for transport_on() and
/// log_map_on(); on the tufted and point-cloud paths its frame path, with frame_basis_3d() of
/// the input.
/// @throws InvalidInput on a refined surface off the manifold path (as direction_field_on())
VectorHeatSolver vector_heat_solver(const PreparedSurface& s);

/// Parallel transport of a 3D vector given at input vertex `source` (projected to its tangent
/// plane, keeping its length) to every input vertex, as 3D tangent vectors (#V_in×3), in the
/// tangent planes of the solver's bases (tangent_basis_3d() on the manifold path, with
/// s.correspondence() when refined; solver.frame_basis() on the frame path). Finite at every vertex
/// the source reaches; NaN (all three coordinates) where it does not: other connected components (a
/// triangle soup's other pieces), unreferenced vertices, and where the heat underflowed, as the
/// report counts (unreached_vertices + unresolved_vertices); heat distance writes inf there.
/// @throws InvalidInput on a source out of range or a vector normal to the surface there, or a
///         solver whose triangulation is not s.tri's (when s has a correspondence)
Eigen::MatrixX3d transport_on(const PreparedSurface& s, const VectorHeatSolver& solver,
                              Index source, const Eigen::Vector3d& vector,
                              VectorHeatReport* report = nullptr);

/// The logarithmic map about input vertex `source`: per input vertex its Riemannian coordinates
/// (u, v) = d·(cos θ, sin θ), d the geodesic distance and θ the direction in which the geodesic
/// leaves the source, counter-clockwise (with the faces' orientation) from the source's
/// reference direction, basis e1 of tangent_basis_3d() at the source (the direction of its
/// first edge; on the frame path e1 of solver.frame_basis(): the x axis projected to the tangent
/// plane, counter-clockwise about the oriented normal).
struct LogMapResult {
  /// #V_in×2: (0, 0) at the source; (NaN, NaN) where VectorHeatSolver::log_map() is undefined
  /// (another component, unreferenced, unresolved)
  Eigen::MatrixX2d uv;
  /// #V_in: d = |(u, v)|; ∞ at vertices no path reaches (another component, unreferenced: as
  /// HeatDistanceSolver), NaN where unresolved
  Eigen::VectorXd distance;
  VectorHeatReport report;  ///< unreached = the ∞ entries; unresolved = the NaN ones
};

/// The log map about `source` by `method` (VectorHeatSolver::log_map()).
/// @throws InvalidInput on a source out of range or unreferenced
LogMapResult log_map_on(const PreparedSurface& s, const VectorHeatSolver& solver, Index source,
                        LogMapMethod method);

/// log_map_on(s, solver, source, LogMapMethod::kBlend).uv (the default method).
/// @throws InvalidInput on a source out of range or unreferenced
Eigen::MatrixX2d log_map_on(const PreparedSurface& s, const VectorHeatSolver& solver, Index source,
                            VectorHeatReport* report = nullptr);

}  // namespace ifem::solvers
