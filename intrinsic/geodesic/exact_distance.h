// Exact polyhedral geodesic distance on an intrinsic triangulation, from its edge lengths alone
// (so it runs on refined, flipped and tufted-cover triangulations as well as on the input):
// window propagation in the manner of Chen & Han, with the improvements of Xin & Wang 2009
// ("Improving Chen and Han's algorithm on the discrete geodesic problem": one window per
// crossing, a priority queue on each window's nearest distance, vertex-distance filters).
// Each window is unfolded in the 2D layout of the face it enters (triangle_apex()); boundary
// vertices and saddle vertices (angle sum > 2π) re-emit as pseudo-sources. Why this algorithm:
// docs/decisions.md D-165.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <utility>
#include <vector>

#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

/// Mollification margin (relative to the robust mean edge length) of the surfaces that measure
/// the input's own lengths: the exact distance and geodesics (CLI, Python, recipes::geodesic).
/// No edge changes unless a face has a margin a + b − c below 1e-12 of the mean edge, i.e.
/// zero area (coincident vertices, collinear corners), which windows would not cross (a vertex
/// behind it unreached or 2.6× too far); then every edge grows by at most that, ~1e-12
/// relative. The other commands' 1e-5 (kDefaultMollifyEpsilon) lengthens every edge of a mesh
/// with a sliver below it, 1e-5..1e-4 on block and rocketship (docs/decisions.md D-350).
inline constexpr double kOwnLengthsMollifyEpsilon = 1e-12;

/// Options of exact_distance().
struct ExactDistanceOptions {
  /// Bytes the windows (and their queue entries) may take; 0: default_memory_budget() (half
  /// the physical memory, refine/delaunay_refine.h). The run stops with InvalidInput stating
  /// the figures when the windows would need more. ≥ 0.
  double max_memory_bytes = 0.0;
  /// Keep every window that survives for ExactDistance::path_to_source() and nearest_source().
  /// false: distances only; the windows are dropped once propagated, so the memory is that of
  /// the windows waiting in the queue (the budget above then bounds those), and the two calls
  /// throw.
  bool keep_paths = true;
};

/// Bytes one window costs against ExactDistanceOptions::max_memory_bytes (the window and its
/// queue entry).
inline constexpr double kExactWindowBytes = 64.0;

/// Result of exact_distance(): distances per vertex and what is needed to trace the shortest
/// path back from any vertex.
class ExactDistance {
 public:
  /// #V of the triangulation: the exact geodesic distance to the nearest source (in the lengths'
  /// unit); +inf on vertices no source reaches (other components, unreferenced vertices).
  Eigen::VectorXd distance;
  std::size_t windows = 0;         ///< windows created (the measure of the work)
  std::size_t pseudo_sources = 0;  ///< saddle and boundary vertices that re-emitted
  bool has_paths = true;           ///< ExactDistanceOptions::keep_paths as run

  /// A shortest path from vertex v to its nearest source, as points of the triangulation: v
  /// first, then every crossing of an edge (a point on a face side) and every vertex it runs
  /// through, the source last (a vertex, or the SurfacePoint given). Its length (straight
  /// segments in the faces between consecutive points) equals distance[v] up to rounding.
  /// Empty when v is unreachable. O(path length).
  /// @throws InvalidInput if v is out of range, or if run without keep_paths
  std::vector<SurfacePoint> path_to_source(Index v) const;

  /// The source the path from v ends at (an index into the sources given); -1 if unreachable.
  /// @throws InvalidInput if run without keep_paths
  Index nearest_source(Index v) const;

  // ===== What path_to_source() reads (filled by exact_distance()) =====
  struct Window {
    double b0, b1;  // interval on the halfedge, distances from its tail
    double ix, iy;  // the source image in the halfedge's frame (tail at 0, head on +x, iy ≤ 0)
    double sigma;   // distance from the source to the image (a pseudo-source's distance)
    Index h;        // the halfedge (the window enters face(h))
    Index parent;   // parent window, or −1 − origin (origin: a vertex, or #V + source index)
  };
  const IntrinsicTriangulation* tri = nullptr;  ///< the triangulation (must outlive the result)
  std::vector<Window> window_store;
  std::vector<Index> vertex_parent;   ///< window id, or −1 − origin, or kNone for a source
  std::vector<double> vertex_x;       ///< where the path crosses the parent window's halfedge
  std::vector<SurfacePoint> sources;  ///< as given (vertex sources as their face corner)
  std::vector<Index> source_vertex;   ///< per source: its vertex, or kInvalidIndex
  static constexpr Index kNone = -2147483647 - 1;
};

/// Exact geodesic distance from the sources (minimum over them) to every vertex of tri, and the
/// path back (ExactDistance::path_to_source()). Sources are surface points of tri (a face and
/// barycentric coordinates; a coordinate of 1 is that corner's vertex, a 0 puts the point on a
/// side). Cost: O(W log W) time for W windows, W·kExactWindowBytes memory (without keep_paths:
/// that of the windows queued at once); W grows about as #F^1.5 on typical meshes (measured
/// figures in BENCHMARKS.md).
/// @throws InvalidInput if sources is empty, a source's face is out of range, its barycentric
///         coordinates are not finite, negative or do not sum to 1 (1e-9); or if the windows
///         exceed the memory budget (the message gives the figures and the option to raise)
ExactDistance exact_distance(const IntrinsicTriangulation& tri,
                             const std::vector<SurfacePoint>& sources,
                             const ExactDistanceOptions& options = {});

/// Same from source vertices (ids of tri).
/// @throws InvalidInput if a vertex is out of range or unreferenced, or as above
ExactDistance exact_distance(const IntrinsicTriangulation& tri, const std::vector<Index>& sources,
                             const ExactDistanceOptions& options = {});

/// Pruning of a window by another on the same halfedge (exact_distance() tries each window it
/// makes against the last one made on its halfedge): what is left of w's interval [b0, b1] once
/// the ends where `other` is at most as long (σ' + |I' x| ≤ σ + |I x|, x in other's interval)
/// are cut off. It cuts only when σ' ≥ σ: the points where `other` is at most w then form a
/// convex set (bounded by a hyperbola branch around I'), so a piece whose two ends it beats is
/// beaten all along, and every point beyond it, ray by ray (when σ' < σ, w may be the shorter
/// in its middle although beaten at both ends: nothing is cut). The crossing that ends a cut
/// piece is a root of a quadratic, checked before use. Both windows in the halfedge's frame
/// (h and parent are not read).
/// @return {b0, b1} of w's part left; b1 ≤ b0 when nothing is left
std::pair<double, double> prune_window_by(const ExactDistance::Window& other,
                                          const ExactDistance::Window& w);

/// Whether a point (px, py) of w's halfedge frame at distance d from the sources (a vertex of
/// face(h) or of the face behind) reaches every point of w's interval [b0, b1] by a straight
/// segment more cheaply than w does, by a relative margin `tie` at both ends (exact_distance()
/// then drops w). When d ≥ σ the points it beats form a convex set, so beating both ends is
/// enough; when d < σ it is w's own set that is convex and w may still be the shorter between
/// two crossings inside (b0, b1) (roots of a quadratic): then the answer is false.
/// False when d is not finite or the interval is empty.
bool point_beats_window(double px, double py, double d, const ExactDistance::Window& w, double tie);

/// The point of face(h)'s corner tail(h) as a SurfacePoint (a vertex as a surface point).
SurfacePoint corner_point(Index h);

}  // namespace ifem::intrinsic
