// Boundary-value problems with data on curves (thesis proposal §5.2, Fig. 10): curves drawn on
// a mesh through its vertices become edges of a constrained intrinsic triangulation (FlipOut
// geodesics, Bézier curves; intrinsic::insert_curves), optionally refined without crossing
// them, and a PDE takes its Dirichlet data exactly on them:
//
//   input mesh + curves ──► prepare_curve_surface(): signposts, FlipOut, constrained Delaunay
//                           flips, optional constrained refinement
//                       ──► curve_poisson()   (L + c·M) u = M f, u = the curves' values on them
//                           curve_distance()  geodesic distance to the curves (heat method)
//                       ──► results on the input's vertices, in the input's order
//
// A curve marked as a slit is a cut: the triangulation is cut open along it, the two sides
// carry their own values, and the solution may jump across it (diffusion curves).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "intrinsic/geodesic/curve_network.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/pipeline.h"

namespace ifem::solvers {

/// A curve through input vertices and the Dirichlet data it carries.
struct CurveCondition {
  /// Input vertex ids (≥ 2; consecutive ones distinct): the waypoints of a geodesic path or
  /// loop (the curve passes through each, in order), or a Bézier curve's control points.
  std::vector<Index> vertices;
  intrinsic::CurveShape shape = intrinsic::CurveShape::kPath;
  int bezier_rounds = 4;  ///< de Casteljau rounds of a kBezier curve, in [0, 16]
  /// The value u takes on the curve: one value (constant), or one per vertex (kPath / kLoop:
  /// linear in arc length between consecutive vertices; a loop closes back to values[0]), or two
  /// for kBezier (at its first and last control point, linear in arc length between). On a slit,
  /// the value on its left side. Empty: the curve carries no value (allowed for distances and as
  /// a pure constraint of the triangulation; curve_poisson() refuses it).
  std::vector<double> values;
  /// A cut: u may jump across the curve; `values` hold on its left side, `right_values` (same
  /// count) on its right. Left: seen from the side the faces' normals point to, walking from
  /// vertices[0] to vertices[1], the left-hand side. The ends of an open slit that lie inside
  /// the surface are single points and take the mean of the two sides' values there.
  bool slit = false;
  std::vector<double> right_values;
  /// Where the curve was given (a curves file's "path:line"), for messages; may be empty.
  std::string origin;
};

/// Reads a curves file: one curve per line, '#' starts a comment, blank lines are skipped.
///   [closed | bezier[=R]] [slit] VALUE v0 v1 ... vk     constant VALUE (slit: LEFT RIGHT)
///   [closed | bezier[=R]] [slit] A0 ... Ak : v0 ... vk  values per vertex (slit: LEFTS : RIGHTS
///                                                       : VERTICES)
/// `closed` makes a loop through the vertices, `bezier` a Bézier curve with them as control
/// points (R rounds, default 4; its values: 1 or 2, at its ends), `slit` a cut with LEFT / RIGHT
/// values. Vertices are 0-based input vertex ids; values finite numbers.
/// @throws IoError naming "path:line" on an unreadable file or a malformed line (the token and
///         what was expected); a file with no curve is an error too
std::vector<CurveCondition> read_curves_file(const std::string& path);

/// One curve as a line of a curves file (no newline): keywords, values (a constant, or lists
/// with ':'), vertex ids; values in the shortest text that reads back exactly (integral ones
/// with ".0", as Python writes them: "1.0"), so
/// read_curves_file() gives the same curve back (its origin aside).
/// @throws InvalidInput naming the curve (origin) when it has no values (every line needs them)
std::string curve_line(const CurveCondition& curve);

/// Writes curves as a curves file that read_curves_file() reads back (one curve_line() a
/// line), atomically (path.tmp, then rename).
/// @throws InvalidInput as curve_line(); IoError if the file cannot be written
void write_curves_file(const std::string& path, const std::vector<CurveCondition>& curves);

/// Checks curves against an input of n_vertices vertices: ids in range, ≥ 2 vertices,
/// consecutive ones distinct, value counts as CurveCondition says, finite values, rounds in
/// range. `need_values`: every curve must carry values (Poisson).
/// @throws InvalidInput naming the curve (its origin, or its index) and what is wrong
void validate_curves(const std::vector<CurveCondition>& curves, Index n_vertices, bool need_values);

/// Options of prepare_curve_surface().
struct CurveSurfaceOptions {
  /// Relative mollification margin of the input (IntrinsicTriangulation::mollify), ≥ 0.
  double mollify_relative_epsilon = intrinsic::kDefaultMollifyEpsilon;
  intrinsic::FlipOutOptions flipout;                 ///< how the curves are shortened
  std::optional<SurfaceRefineOptions> refine;        ///< constrained Delaunay refinement when set
                                                     ///< (relaxation is not offered with curves)
  std::function<void(const std::string&)> progress;  ///< one line per stage; none when empty
  /// Progress of the constrained refinement (RefineOptions::on_progress); empty: none
  ProgressCallback on_progress;
  /// Memory budget, bytes, of the vertices Bézier curves add (intrinsic::estimate_curves(),
  /// checked before any flip); 0: intrinsic::default_memory_budget(). With refine, its
  /// max_memory_bytes applies to the refinement.
  double max_memory_bytes = 0.0;
  /// Accept curves whose shortening stopped at FlipOut's iteration cap (flipout.max_iterations)
  /// before they were geodesic: false refuses them (InvalidInput stating what was reached).
  bool accept_partial = false;
  /// @throws InvalidInput naming the field (mollify_relative_epsilon, flipout, refine,
  ///         max_memory_bytes)
  void validate() const;
};

/// A surface with curves as edges of its intrinsic triangulation.
struct CurveSurface {
  /// The input, its reports and h, as prepare_surface() gives them, with `tri` the constrained
  /// intrinsic Delaunay triangulation (refined when asked; slits not cut: curve_poisson() cuts a
  /// copy) and its correspondence: `signposts`, or `integer` when refined with
  /// SurfaceRefineOptions::correspondence = integer.
  PreparedSurface surface;
  std::vector<CurveCondition> curves;       ///< as given
  intrinsic::CurveNetwork network;          ///< the curves as constrained edges of surface.tri
  intrinsic::FlipReport constrained_flips;  ///< constrained Delaunay flips after the curves
  intrinsic::CotanSigns signs;              ///< cotan weights' signs at the end
  double seconds_curves = 0;
  Index n_input_vertices() const { return surface.n_input_vertices(); }
};

/// Builds the signpost triangulation of an edge-manifold, orientable mesh, inserts the curves
/// (intrinsic::insert_curves: FlipOut through the given vertices, Bézier curves), flips to the
/// constrained intrinsic Delaunay triangulation, and refines it when asked (constrained:
/// curves are split, never crossed). With integer coordinates (options.refine->correspondence)
/// the signposts' operations are replayed on a NormalCoordinateTriangulation
/// (intrinsic::replay_on_integer), which is then refined and kept instead (D-260).
/// @throws InvalidInput on bad curves (validate_curves; need_values false), a point cloud or a
///         mesh that is not edge-manifold and orientable (curves need signposts), overlapping
///         curves, Bézier curves over the budget (intrinsic::insert_curves), curves FlipOut left
///         at its iteration cap (unless accept_partial), curves that leave triangles of zero
///         area (named by origin, never by internal ids), bad options, a replay on integer
///         coordinates that does not give the signposts' triangulation
/// @throws NonManifoldInput from the mesh build
CurveSurface prepare_curve_surface(io::SurfaceInput input, std::vector<CurveCondition> curves,
                                   const CurveSurfaceOptions& options = {});

/// Result of curve_poisson().
struct CurvePoissonResult {
  Eigen::VectorXd u;            ///< #V_in: u on the input's vertices, in their order (a vertex on a
                                ///< slit: the mean of its sides' values)
  Eigen::VectorXd u_intrinsic;  ///< #V of s.st.intrinsic() (same convention on slits)
  Index dirichlet_vertices = 0;    ///< intrinsic vertices (slit sides counted apart) held fixed
  Index conflicting_vertices = 0;  ///< vertices where curves meet with different values (they
                                   ///< get the mean), slit tips included
  Index slit_copies = 0;           ///< vertices added by cutting the slits open
};

/// Solves (L + c·M) u = M f on the constrained triangulation, with u = the curves' values on
/// every vertex of every curve (both sides of slits), plus u = dirichlet_values on the given
/// input vertices, natural conditions elsewhere. f is given on the input's vertices (#V_in; empty:
/// 0) and interpolated onto inserted vertices.
/// @throws InvalidInput on a curve without values, sizes, ids out of [0, #V_in), a Dirichlet
///         vertex on a curve
/// @throws SolverError if the factorization fails
CurvePoissonResult curve_poisson(const CurveSurface& s, const Eigen::VectorXd& f,
                                 const std::vector<Index>& dirichlet_vertices = {},
                                 const Eigen::VectorXd& dirichlet_values = {},
                                 const PoissonOptions& options = {});

/// Geodesic distance to the union of the curves (heat method on the constrained triangulation,
/// every curve vertex a source: exactly 0 on the curves), on the input's vertices (#V_in).
/// Settings as geodesic_distance(); h is the input's.
/// @throws SolverError if a factorization fails
Eigen::VectorXd curve_distance(const CurveSurface& s, const DistanceOptions& settings = {},
                               HeatDistanceReport* report = nullptr);

/// The curves as 3D polylines (traced over the input with the signposts or the integer
/// coordinates), one per curve, in the order given; a loop repeats its first point.
/// @throws InvalidInput when s has neither correspondence
std::vector<std::vector<Eigen::Vector3d>> curve_polylines(const CurveSurface& s);

}  // namespace ifem::solvers
