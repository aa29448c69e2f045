// Geodesic paths by edge flips: FlipOut (Sharp & Crane 2020, "You Can Find Geodesic Paths in
// Triangle Meshes by Just Flipping Edges"). A curve made of intrinsic edges is shortened by
// flipping the edges inside a wedge where it bends by less than π, until it can be rerouted
// along the wedge's outer boundary; at convergence every wedge angle at an interior curve vertex
// is ≥ π − ε on both sides, so the curve is a locally shortest (geodesic) curve on the surface.
// All flips go through SignpostTriangulation::flip_edge, so the curves can be traced over the
// input mesh afterwards, and the triangulation left behind has the curves among its edges
// (curve_edge_flags()): a triangulation conforming to the curves.
//
// Units: lengths in the unit of the triangulation's edge lengths; angles in radians.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "intrinsic/core/progress.h"
#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/types.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// One step of an edge path: intrinsic edge `edge`, traversed along edge_halfedge(edge) when
/// `forward`, else against it. Steps are stored by edge id (stable under flips of other
/// edges), not by halfedge slot (a flip moves the slots of its diamond's sides).
struct PathStep {
  Index edge = kInvalidIndex;
  bool forward = true;
};

/// A curve along intrinsic edges: steps[i] ends where steps[i+1] starts (by halfedge identity,
/// so self-edges and repeated vertices are fine). `closed`: a loop, the last step ends where
/// the first starts. `pinned`: vertices the curve must keep passing through, as indices of the
/// joint they sit at (joint i is where steps[i−1] meets steps[i]; for a loop joint 0 is where
/// the last step meets the first); a pinned joint may stay bent. The two ends of an open path
/// are always fixed. An open path with no steps is a single vertex; a loop with none has
/// shrunk to a point.
struct EdgePath {
  std::vector<PathStep> steps;
  bool closed = false;
  std::vector<Index> pinned;
};

/// The halfedge that traverses `step` in its direction, or kInvalidIndex when it runs against a
/// boundary side (that side has no twin).
Index step_halfedge(const IntrinsicTriangulation& tri, const PathStep& step);
/// The vertex a step starts at / ends at.
Index step_tail(const IntrinsicTriangulation& tri, const PathStep& step);
Index step_head(const IntrinsicTriangulation& tri, const PathStep& step);

/// The vertices a path passes through, in order (#steps + 1 entries for an open path, #steps
/// for a loop).
std::vector<Index> path_vertices(const IntrinsicTriangulation& tri, const EdgePath& path);

/// Sum of the intrinsic lengths of the path's steps (length unit of tri).
double path_length(const IntrinsicTriangulation& tri, const EdgePath& path);

/// A shortest path from vertex a to vertex b along intrinsic edges (Dijkstra on edge lengths).
/// @throws InvalidInput if a or b is out of range, a == b, or b is not reachable from a (they
///         lie on different connected components)
EdgePath shortest_edge_path(const IntrinsicTriangulation& tri, Index a, Index b);
EdgePath shortest_edge_path(const SignpostTriangulation& st, Index a, Index b);

/// How edge_path_through() joins two consecutive vertices.
enum class JoinBy {
  kDijkstra,     ///< always a shortest edge path
  kDirectEdges,  ///< the edge between them when they are adjacent (on an unflipped signpost
                 ///< triangulation: the input edge), else a shortest edge path
};

/// A path through `vertices` in order (≥ 2 of them, for a loop too: its last vertex is joined
/// back to the first), every consecutive pair joined as `join` says. With `pin`, every given vertex
/// except the two ends of an open path becomes a pinned joint (a path through waypoints);
/// without it only the ends of an open path stay (the vertices shape the initial curve only).
/// @throws InvalidInput naming the offending position: a vertex out of range, two equal
///         consecutive vertices (also last/first of a loop), fewer vertices than needed, or
///         two consecutive vertices on different connected components
EdgePath edge_path_through(const IntrinsicTriangulation& tri, const std::vector<Index>& vertices,
                           bool closed, bool pin, JoinBy join = JoinBy::kDijkstra);

/// edge_path_through() for many curves on one unchanged triangulation: the edge graph is built
/// once and the search's arrays are reused (reset only where a search went), so n curves cost
/// one graph and their searches, not n × #E. Valid while tri's connectivity does not change.
class EdgePathFinder {
 public:
  explicit EdgePathFinder(const IntrinsicTriangulation& tri);
  ~EdgePathFinder();
  EdgePathFinder(const EdgePathFinder&) = delete;
  EdgePathFinder& operator=(const EdgePathFinder&) = delete;
  /// Same contract as edge_path_through(tri, vertices, closed, pin, join).
  EdgePath through(const std::vector<Index>& vertices, bool closed, bool pin,
                   JoinBy join = JoinBy::kDijkstra);
  struct EdgeGraph;

 private:
  const IntrinsicTriangulation& tri_;
  std::unique_ptr<EdgeGraph> graph_;
};

/// The two wedge angles at joint i of the path (see EdgePath; 1 ≤ i < #steps for an open
/// path, 0 ≤ i < #steps for a loop): [0] swept counter-clockwise from the outgoing step to the
/// reversed incoming one, [1] from the reversed incoming step to the outgoing one, each a sum
/// of corner angles (radians); together they make the vertex's total angle. A wedge that would
/// sweep over the boundary is +∞: at a boundary vertex only the wedge on the interior side
/// counts (a path may hug the boundary). Both are 0 at a backtrack (steps i − 1 and i: one
/// edge, both ways).
Eigen::Vector2d wedge_angles(const IntrinsicTriangulation& tri, const EdgePath& path, Index i);

/// The smallest wedge angle over all joints that are not pinned (+∞ if there is none).
double min_wedge_angle(const IntrinsicTriangulation& tri, const EdgePath& path);

/// How shorten() runs.
struct FlipOutOptions {
  /// Converged when every wedge angle at an unpinned joint is ≥ π − angle_epsilon (radians, in
  /// [0, π)). At a boundary vertex only the wedge not containing the boundary counts.
  double angle_epsilon = 1e-6;
  /// At most this many reroutes (FlipOut steps) in all; −1: 10 × #E + 1000.
  Index max_iterations = -1;
  /// Stop when a round of reroutes (as many as the curves have joints, at least 100) shortens
  /// the curves by less than this fraction of their length (in [0, 1)); 0: never.
  double min_relative_decrease = 1e-14;
  /// @throws InvalidInput naming the field on a value outside its range
  void validate() const;
};

/// Why shorten() stopped.
enum class FlipOutStop {
  kConverged,     ///< every unpinned wedge angle ≥ π − ε
  kIterationCap,  ///< max_iterations reroutes done
  kNoProgress,    ///< a round of reroutes gained less than min_relative_decrease
  kBlocked,       ///< the remaining bends cannot be straightened: their wedges hold edges of
                  ///< curves (straightening would cross them) or edges that cannot be flipped
};

/// A readable name for a FlipOutStop ("converged", "iteration cap", ...).
const char* to_string(FlipOutStop stop);

/// What shorten() did.
struct FlipOutReport {
  double initial_length = 0.0;  ///< total over all curves
  double final_length = 0.0;
  Index flips = 0;       ///< edge flips performed
  Index iterations = 0;  ///< reroutes performed (backtracks removed included)
  FlipOutStop stopped_by = FlipOutStop::kConverged;
  Index blocked_joints = 0;            ///< bent joints left unstraightened (kBlocked)
  std::vector<double> lengths;         ///< per curve, final
  std::vector<Index> collapsed_loops;  ///< loops that shrank to a point (no steps left) or to
                                       ///< a self-edge around one vertex it cannot pass:
                                       ///< contractible loops; reported, never spun on
};

/// Shortens `paths` together by FlipOut, always at the currently smallest wedge angle first
/// (a network: curves may share vertices and edges but must not cross transversely; a wedge
/// holding an edge of any curve is not flipped, so no new crossing appears). Edges flagged in
/// `fixed_edges` (#E of st.intrinsic(), when given) are never flipped either (constraints).
/// Flips edges of st (the surface is unchanged; the triangulation and signposts change); the
/// ends of open paths and pinned joints stay, every curve's length never increases.
/// @throws InvalidInput on bad options or a path whose steps are not consecutive (naming the
///         curve and step), a pinned joint out of range, or fixed_edges of the wrong size
FlipOutReport shorten(SignpostTriangulation& st, std::vector<EdgePath>& paths,
                      const FlipOutOptions& options = {},
                      const std::vector<char>* fixed_edges = nullptr);
/// One curve (same contract).
FlipOutReport shorten(SignpostTriangulation& st, EdgePath& path,
                      const FlipOutOptions& options = {});

/// #E flags of st.intrinsic(): 1 on every edge some path runs along (the curves as edges of the
/// triangulation, for code that must keep them: e.g. as constraints of later flips).
std::vector<char> curve_edge_flags(const IntrinsicTriangulation& tri,
                                   const std::vector<EdgePath>& paths);

/// The path as points of the input surface: every step traced over the input with the
/// signposts (SignpostTriangulation::trace_halfedge), joints shared; a loop repeats its first
/// point at the end. Faces refer to st.input().
/// @throws TraceError when a step cannot be traced
std::vector<SurfacePoint> path_surface_points(const SignpostTriangulation& st,
                                              const EdgePath& path);
/// The same as 3D positions. Its 3D length equals path_length() up to tracing round-off (and
/// the mollification, if any).
std::vector<Eigen::Vector3d> path_polyline(const SignpostTriangulation& st, const EdgePath& path);

/// Where a point of the input surface lies on st's intrinsic triangulation (any state: flips,
/// insertions): traced from the nearest corner of input face f (of st.input()), at the distance
/// and angle the point has in f's layout. Nothing is inserted.
/// @param b barycentric coordinates in f, ≥ 0, summing to 1 (not checked here)
/// @throws InvalidInput if that corner has no faces; TraceError when the trace fails
SurfacePoint locate_input_point(const SignpostTriangulation& st, Index f, const Eigen::Vector3d& b);

/// Inserts a point of the input surface (face of st.input(), barycentric coordinates ≥ 0
/// summing to 1 within 1e-9) as an intrinsic vertex and returns its id: an existing vertex when
/// the point is one (a barycentric coordinate ≥ 1 − `snap`, in the input face or in the
/// intrinsic face it lands in), a split of the intrinsic edge it lies on (a coordinate ≤ snap),
/// else a new vertex inside an intrinsic face. Works on any state
/// of st (flips and earlier insertions): the point is found by tracing from an input corner.
/// @throws InvalidInput naming the face or coordinates when they are out of range
/// @throws TraceError when the trace fails (degenerate input)
Index insert_surface_point(SignpostTriangulation& st, const SurfacePoint& input_point,
                           double snap = 1e-9);

/// A geodesic Bézier curve by de Casteljau subdivision with geodesic segments (Sharp & Crane
/// 2020, after Morera, Carvalho & Velho 2008): each round replaces every Bézier piece of
/// degree d by its two halves at t = 1/2, the midpoints taken halfway along FlipOut geodesics
/// between the previous points (inserted as vertices, splitting an edge); after `rounds` rounds
/// the control polygon (d·2^rounds + 1 points), joined by FlipOut geodesics pinned at every
/// control point, is the curve.
struct BezierCurve {
  EdgePath path;                ///< the final control polygon, pinned at every control point
  std::vector<Index> controls;  ///< its control points (intrinsic vertex ids), in order
  Index inserted_vertices = 0;  ///< midpoints inserted
  FlipOutReport report;         ///< of the final shortening
};
/// @param control ≥ 2 intrinsic vertex ids (degree = #control − 1); consecutive ones distinct
/// @param rounds ≥ 0 (0: the geodesic control polygon itself); at most 16
/// @param fixed_edges optional #E flags (shorter is fine: missing entries are 0) of edges never
///        flipped or split (other curves already in the triangulation): a midpoint that would
///        split one snaps to its nearer end
/// @throws InvalidInput on bad control points or rounds, or points on different components
BezierCurve bezier_curve(SignpostTriangulation& st, const std::vector<Index>& control, int rounds,
                         const FlipOutOptions& options = {},
                         const std::vector<char>* fixed_edges = nullptr);

/// Single-source geodesics (Sharp & Crane 2020, §6.4; thesis proposal §5.3): a Dijkstra search
/// from `source` that makes every accepted path a geodesic by FlipOut before accepting it,
/// holding the paths accepted earlier fixed (their edges are never flipped), so that at the end
/// the triangulation contains a geodesic from the source to every reached vertex as an edge
/// path. A vertex is reached from the accepted neighbour u that minimizes the unfolded length:
/// the straight distance from the start of u's geodesic's last straight run, laid out across
/// the wedge at u (the edge path's length through u where no wedge < π is measured: boundary,
/// pinched vertex). Its start path is u's geodesic and the edge to it; when FlipOut leaves that
/// path bent (blocked by accepted paths), up to 8 other accepted neighbours' starts are
/// shortened too, best unfolded length first, until one converges; when it converges, those
/// whose unfolded length is within 1e-5 of the length found (the other side of a vertex of
/// positive curvature) are. The shortest result is kept; losers' flips stay (the surface is
/// unchanged). Lengths are those geodesics' lengths: ≥ the exact distance, equal to it whenever
/// the geodesic found is the shortest one (not guaranteed; 94.6–100% of the vertices on the
/// reference meshes, 40–77% on one of slivers: docs/decisions.md D-144).
struct SingleSourceGeodesics {
  Eigen::VectorXd length;        ///< #V (intrinsic vertices at the call): +∞ where unreachable
  std::vector<EdgePath> paths;   ///< #V: the geodesic to each vertex (empty: source, unreached)
  std::vector<char> tree_edges;  ///< #E: edges some accepted path runs along
  Index flips = 0;
  Index iterations = 0;
  Index blocked = 0;  ///< vertices whose path was left bent (a blocked wedge)
};
/// @param on_progress optional: stage "single-source geodesics", vertices accepted over #V
/// @throws InvalidInput if source is out of range or options are invalid
SingleSourceGeodesics single_source_geodesics(SignpostTriangulation& st, Index source,
                                              const FlipOutOptions& options = {},
                                              const ProgressCallback& on_progress = {});

}  // namespace ifem::intrinsic
