// The geodesic recipe: geodesic paths, loops, networks and Bézier curves by FlipOut (Sharp &
// Crane 2020: edge flips on a signpost intrinsic triangulation of the input), traced over the
// input surface; or single-source geodesics from one vertex. What `ifem geodesic` and
// `ifem.geodesic` (Python) run:
//
//   input mesh + points ──► signposts (intrinsic::flipout_surface)
//                       ──► face points inserted as vertices, edge paths through the points
//                       ──► FlipOut (all curves together: they never cross) or de Casteljau
//                       ──► polylines on the input surface, lengths, FlipOut's report
//
// FlipOut needs an edge-manifold, orientable triangle mesh (with or without boundary). On a
// nonmanifold or non-orientable mesh (which the signposts refuse) a path between two points and
// single-source geodesics are the exact distance's shortest paths on the input's tufted cover
// (the surface `ifem distance --exact` measures: each cover face a copy of an input face, so a
// path on the cover is a path on the input of the same length); loops, networks, several
// points and Bézier curves are refused there (docs/decisions.md D-375).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "intrinsic/geodesic/exact_distance.h"
#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/geodesic/guided_path.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::solvers {
struct PreparedSurface;
class HeatDistanceSolver;
}  // namespace ifem::solvers

namespace ifem::recipes {

/// Options of geodesic().
struct GeodesicOptions {
  /// Relative mollification margin of the signpost triangulation, in [0, 1]; by default the
  /// input's own lengths (zero-area faces lifted by ~1e-12: intrinsic::kOwnLengthsMollifyEpsilon).
  double mollify_relative_epsilon = intrinsic::kOwnLengthsMollifyEpsilon;
  /// Set: one open curve whose points are the control points of a geodesic Bézier curve, with
  /// this many rounds of de Casteljau subdivision, in [0, 16] (0: the geodesic control polygon).
  std::optional<int> bezier_rounds;
  /// Single-source mode: also trace every geodesic over the input (the exact distance's paths
  /// back: O(path length) each; with FlipOut about one more search).
  bool trace_paths = false;
  /// Single-source mode: false (default) takes the lengths and paths from the exact distance
  /// (intrinsic::exact_distance on the signpost triangulation as built: the shortest geodesics,
  /// no flip); true builds every geodesic by FlipOut (intrinsic::single_source_geodesics: edge
  /// paths of the triangulation, locally shortest, not always the shortest ones). When the
  /// exact distance's windows exceed the memory budget (max_memory_bytes), FlipOut is used.
  bool single_source_flipout = false;
  intrinsic::FlipOutOptions flipout;  ///< how curves are shortened (iteration cap, ...)
  /// Curves that stopped at FlipOut's iteration cap are not geodesic: false refuses them
  /// (InvalidInput stating what was reached), true returns them as they are.
  bool accept_partial = false;
  /// Memory budget, bytes, of the vertices a Bézier curve adds (intrinsic::check_curve_budget(),
  /// before any flip) and of the exact distance's windows in single-source mode and, on a
  /// nonmanifold input, for a path between two points; 0: intrinsic::default_memory_budget().
  double max_memory_bytes = 0.0;
  /// FlipOut's start paths for one open path between two points (intrinsic::shortest_geodesic):
  /// kBest (default) shortens the Dijkstra edge path and the start paths of StartGuide (the
  /// exact geodesic's strip from each end point, intrinsic::exact_edge_path, the exact distance
  /// to the start point computed only when the first strip falls short; over the exact
  /// distance's memory budget, six paths down a heat distance to each end point), each with the
  /// search over neighbouring classes, and keeps the shortest. Its cost is the guide plus at
  /// most 7 such searches, all on one triangulation whose flips are undone between them (no
  /// copies); kGuided the guided ones only; kDijkstra the Dijkstra path
  /// alone (one FlipOut: fastest, but FlipOut keeps its start's class, so the geodesic is more
  /// often not the shortest one). Other curves (loops, networks, several points, Bézier) always
  /// start from Dijkstra edge paths, shortened together.
  intrinsic::StartPath start = intrinsic::StartPath::kBest;
  /// Progress of single-source mode (intrinsic::single_source_geodesics()'s, stage
  /// "single-source geodesics"); empty: none.
  ProgressCallback on_progress;
  /// @throws InvalidInput naming the field and its allowed range
  void validate() const;
};

/// One curve once shortened, on the input surface.
struct GeodesicCurve {
  std::vector<Eigen::Vector3d> polyline;  ///< in order along the curve; a loop repeats its start
  std::vector<Eigen::Vector3d> points;    ///< the given points' positions, in the order given
  double initial_length = 0.0;            ///< the edge path's length before FlipOut
  double length = 0.0;                    ///< after FlipOut (intrinsic: exact on the surface)
  bool closed = false;
  bool collapsed = false;  ///< a loop that shrank to a point (or around one vertex)
};

/// A face point inserted as a vertex of the signpost triangulation before the curves are built.
struct InsertedPoint {
  std::string token;  ///< the point as given (GivenPoint::token)
  Index vertex = kInvalidIndex;
  bool snapped = false;  ///< it fell on an existing vertex (within 1e-9 of it)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// What geodesic() computed for curves.
struct GeodesicCurves {
  std::vector<GeodesicCurve> curves;  ///< one per given curve, in order
  intrinsic::FlipOutReport report;    ///< of all the curves together
  std::vector<InsertedPoint> inserted;
  Index bezier_control_points = 0;  ///< Bézier: control points after subdivision
  Index bezier_midpoints = 0;       ///< Bézier: midpoints inserted
  double seconds_signposts = 0.0, seconds_flipout = 0.0;
  double seconds_guide = 0.0;  ///< StartGuide's seconds (exact distances or heat) (0: not used)
  /// The start path the kept geodesic came from (intrinsic::shortest_geodesic()'s `won`) for a
  /// path between two points; empty for other curves. "exact path (...)" when the path is the
  /// exact distance's shortest path instead of FlipOut's: FlipOut's kept geodesic was longer
  /// than the exact distance by more than kExactPairTolerance (the parenthesis says from which
  /// start and by how much), or the input is nonmanifold ("exact path (tufted cover)").
  std::string start_won;
  /// True: the input is not edge-manifold and orientable and the one path between two points is
  /// the exact shortest path on its tufted cover (no FlipOut: `report` is empty, `windows` the
  /// exact distance's work).
  bool tufted_cover = false;
  std::size_t windows = 0;  ///< tufted_cover: windows of the exact distance
};

/// A path between two points is FlipOut's geodesic unless that is longer than the exact
/// distance between them by more than this (relative): then the exact distance's path is
/// returned instead (GeodesicCurves::start_won "exact path ..."). Both lengths are sums over
/// the same intrinsic edge lengths; where they describe the same geodesic they agreed to ≤ 5e-14
/// on 55 reference pairs (rounding over a few hundred segments), while the FlipOut geodesics in
/// another class were 1e-6–4.4e-3 longer (the 7 of 208 audit pairs that fall back; generated
/// bumpy grids: ≥ 8e-5); 1e-9 separates the two with margins of 10⁴ and 10³
/// (docs/decisions.md D-375).
inline constexpr double kExactPairTolerance = 1e-9;

/// What geodesic() computed from one source vertex.
struct SingleSourceResult {
  Eigen::VectorXd length;  ///< #V_in: each vertex's geodesic length, +∞ where unreachable
  /// With trace_paths: one polyline per input vertex (the source's: its own position;
  /// unreachable: empty); else empty.
  std::vector<std::vector<Eigen::Vector3d>> paths;
  /// True: lengths and paths from the exact distance (shortest geodesics); false: FlipOut's.
  bool exact = false;
  /// True: the input is not edge-manifold and orientable, and the exact distance ran on its
  /// tufted cover (paths on the cover are paths on the input: same points, same lengths).
  bool tufted_cover = false;
  std::size_t windows = 0;          ///< exact: the exact distance's windows (its work)
  Index flips = 0, iterations = 0;  ///< FlipOut: its flips and iterations
  Index blocked = 0;  ///< FlipOut: vertices whose path was left bent (a blocked wedge)
  double seconds = 0.0;
};

/// The guide of FlipOut's start paths: the exact distance (intrinsic::exact_distance) on st's own
/// triangulation, whose traced geodesics give the start paths themselves
/// (intrinsic::exact_edge_path; docs/decisions.md D-200). When its windows exceed the memory
/// budget (intrinsic::default_memory_budget()), a heat distance for intrinsic::descent_edge_path:
/// up to 20,000 input vertices the accurate one (`ifem distance --refine`: refined to edges of
/// about 0.4·h) on a signpost triangulation of the input, above (or when the refinement is
/// refused) the heat method on the input's intrinsic Delaunay triangulation; its refinement and
/// factorization happen at the first heat call, later calls cost a heat solve.
class StartGuide {
 public:
  /// @param input the mesh st was built from (flipout_surface); kept by reference
  explicit StartGuide(const io::SurfaceInput& input);
  ~StartGuide();
  /// #V of st.intrinsic(): ≈ the distance to `target` (exact when exact_to_each() is not
  /// refused; the heat guide at an inserted vertex: to the nearest corner of its input face,
  /// linear over input faces); +∞ where unreachable.
  Eigen::VectorXd to(const intrinsic::SignpostTriangulation& st, Index target);
  /// to() for each target, one column each (the heat solves batched: cheaper than one by one).
  Eigen::MatrixXd to_each(const intrinsic::SignpostTriangulation& st,
                          const std::vector<Index>& targets);
  /// The exact distance on st.intrinsic() (as it is now) from each target, in order; empty when
  /// the windows exceed the memory budget (then every later call is empty at once). Cost about
  /// #F^1.5 windows per target (BENCHMARKS.md, "Exact geodesic distance").
  std::vector<intrinsic::ExactDistance> exact_to_each(const intrinsic::SignpostTriangulation& st,
                                                      const std::vector<Index>& targets);
  double seconds = 0.0;  ///< spent in to(), to_each() and exact_to_each() so far

 private:
  void build();
  const io::SurfaceInput& input_;
  std::unique_ptr<solvers::PreparedSurface> surface_;
  std::unique_ptr<solvers::HeatDistanceSolver> solver_;
  bool exact_refused_ = false;
};

/// "" when p names a vertex / face of `input` (a face point also needs a triangle mesh), else
/// what is wrong (naming the point and the range).
std::string point_problem(const GivenPoint& p, const io::SurfaceInput& input);

/// Checks every curve: ≥ 2 points, each as point_problem() and, for a vertex, used by some
/// face (an isolated vertex is not on the surface), no repeated consecutive points.
/// @throws InvalidInput "ORIGIN: problem"
void check_curves(const std::vector<GivenCurve>& curves, const io::SurfaceInput& input);

/// Geodesic curves through the given points (paths, loops, a network shortened together; with
/// options.bezier_rounds one Bézier curve), traced over the input. A path between two points
/// is never longer than the exact distance between them (kExactPairTolerance) while the exact
/// distance fits the memory budget.
/// On a mesh that is not edge-manifold and orientable, one open curve through two points
/// (vertices or face points) is the exact shortest path on the tufted cover
/// (GeodesicCurves::tufted_cover; options.start is not used).
/// @throws InvalidInput on bad options or curves (check_curves), an input without faces or
///         area, points on different components, a Bézier curve over its budget
///         (intrinsic::check_curve_budget), curves left at FlipOut's iteration cap (unless
///         accept_partial; intrinsic::iteration_cap_message); on the tufted cover: the exact
///         distance over the memory budget
/// @throws NonManifoldInput on a mesh that is not edge-manifold and orientable, for anything
///         but one path between two points (loops, networks, several points, Bézier: FlipOut
///         needs signposts), saying what does run on such a mesh
GeodesicCurves geodesic(const io::SurfaceInput& input, const std::vector<GivenCurve>& curves,
                        const GeodesicOptions& options = {});

/// Single-source geodesics: a geodesic from `source` to every vertex and their lengths: the
/// shortest ones from the exact distance (default), or by FlipOut (Dijkstra with FlipOut at the
/// frontier; GeodesicOptions::single_source_flipout). On a mesh that is not edge-manifold and
/// orientable: the exact distance on its tufted cover (SingleSourceResult::tufted_cover), as
/// `ifem distance --exact` computes it, its paths mapped onto the input.
/// @throws InvalidInput on a source outside [0, #V_in) or used by no face, bad options, an input
///         without faces; on the tufted cover, the exact distance over the memory budget (no
///         FlipOut to fall back on)
/// @throws NonManifoldInput with single_source_flipout on a mesh that is not edge-manifold and
///         orientable (FlipOut needs signposts)
SingleSourceResult geodesic(const io::SurfaceInput& input, Index source,
                            const GeodesicOptions& options = {});

}  // namespace ifem::recipes
