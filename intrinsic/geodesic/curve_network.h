// Curves as edges of a constrained intrinsic triangulation (thesis proposal §5.2): curves through
// vertices are made geodesic by FlipOut (paths, loops, Bézier curves), their edges are marked
// constrained, and from then on Delaunay flips never flip them and Delaunay refinement never
// crosses them (a point that would land across one splits it instead, as boundary edges are
// split). The result is a constrained Delaunay triangulation: every unconstrained interior edge is
// Delaunay.
//
// Each curve edge remembers its curve, its direction along the curve and the arc length (from the
// curve's start) at its two ends; refinement splits keep that up to date (the new vertex gets the
// interpolated arc length: exact, since a curve edge is a straight segment of the surface), so
// data given along a curve (values linear in arc length) can be put on every vertex of it.
#pragma once

#include <vector>

#include "intrinsic/geodesic/flip_geodesic.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::intrinsic {

/// How a curve runs through its vertices.
enum class CurveShape {
  kPath,    ///< open geodesic through the vertices in order (pinned at each)
  kLoop,    ///< closed geodesic through them, back to the first
  kBezier,  ///< geodesic Bézier curve with them as control points (bezier_curve())
};

/// A curve to insert: intrinsic vertex ids (≥ 2, consecutive ones distinct).
struct CurveSpec {
  std::vector<Index> vertices;
  CurveShape shape = CurveShape::kPath;
  int bezier_rounds = 4;  ///< for kBezier, in [0, 16]
};

/// Per edge of the triangulation: the curve it belongs to, if any.
struct CurveEdge {
  Index curve = kInvalidIndex;  ///< kInvalidIndex: not a curve edge
  bool forward = true;          ///< the curve runs along edge_halfedge(e) (else against it)
  double s_tail = 0.0;          ///< arc length from the curve's start at tail(edge_halfedge(e))
  double s_head = 0.0;          ///< ... at its head (a loop's last edge ends at its length)
  Index prev = kInvalidIndex;   ///< the curve's previous / next edge (kInvalidIndex at an end
  Index next = kInvalidIndex;   ///< of an open curve)
};

/// Curves held as constrained edges. Kept in step with the triangulation by the operations
/// below (flips never touch constrained edges; refinement splits update it).
struct CurveNetwork {
  std::vector<char> constrained;  ///< #E: 1 on curve edges (and any other constrained edge)
  std::vector<CurveEdge> edges;   ///< #E
  std::vector<Index> first_edge;  ///< per curve: its first edge (kInvalidIndex: no edge)
  std::vector<char> closed;       ///< per curve
  std::vector<double> length;     ///< per curve, total arc length
  /// Per curve, the arc length at each of its control points: the given vertices of a path or
  /// loop (a loop's list ends with its length, back at the first vertex), or the two ends of a
  /// Bézier curve.
  std::vector<std::vector<double>> control_arclength;
  FlipOutReport flipout;       ///< of shortening the paths and loops together
  Index bezier_midpoints = 0;  ///< vertices inserted by Bézier subdivision
  Index n_curves() const { return static_cast<Index>(first_edge.size()); }
  /// The constraint set for delaunay_refine() on tri (the triangulation the network lives in),
  /// updating this network on splits. Both must outlive its use, at the same addresses.
  EdgeConstraints constraints(const IntrinsicTriangulation& tri);
};

/// What inserting curves adds, estimated before any flip (one edge-path search per Bézier
/// curve). A Bézier curve of degree d = #control − 1 and R rounds splits 2^R − 1 pieces and
/// inserts d(d+1)/2 midpoints per split: at most d(d+1)/2 · (2^R − 1) vertices (fewer where a
/// midpoint is an existing vertex). Its final control polygon has d·2^R segments of about
/// L / (d·2^R), L the length of the shortest edge path through its control points (≥ the
/// curve's length, so the figure is generous). Paths and loops add no vertex.
struct CurveEstimate {
  std::vector<double> added_vertices;  ///< per curve (0 for paths and loops)
  std::vector<double> segment_length;  ///< per Bézier curve: L / (d·2^R) (0 for the others)
  double vertices = 0.0;               ///< #V + every curve's added vertices
  double bytes = 0.0;                  ///< vertices × kRefineBytesPerVertex
  double budget = 0.0;                 ///< the memory budget compared with
  double mean_edge_length = 0.0;       ///< h: robust mean of the triangulation's edge lengths
};

/// Bézier segments shorter than this × h (CurveEstimate) are refused: subdivision below the
/// mesh's resolution inserts midpoints a round-off apart (triangles of zero area) and shows
/// nothing the mesh can resolve (docs/decisions.md D-137).
inline constexpr double kMinBezierSegment = 1.0 / 16.0;

/// The estimate above for specs on tri (specs checked as insert_curves() does); budget:
/// max_memory_bytes, or default_memory_budget() when 0.
/// @throws InvalidInput as insert_curves() on bad specs
CurveEstimate estimate_curves(const IntrinsicTriangulation& tri,
                              const std::vector<CurveSpec>& specs, double max_memory_bytes = 0.0);

/// Refuses the first Bézier curve of specs whose estimate (estimate_curves(), all curves
/// counted) exceeds the memory budget (max_memory_bytes; 0: default_memory_budget()) or whose
/// segments fall below kMinBezierSegment·h, stating the figures and the most rounds that fit.
/// @throws InvalidInput naming the curve (by index) as said, or as insert_curves() on bad specs
void check_curve_budget(const IntrinsicTriangulation& tri, const std::vector<CurveSpec>& specs,
                        double max_memory_bytes = 0.0);

/// The refusal of curves FlipOut left at its iteration cap: what was reached (reroutes, flips,
/// total length before → after), that the result is not geodesic, and how to go on (raise
/// FlipOutOptions::max_iterations, or `accept`, the caller's option that accepts it).
std::string iteration_cap_message(const FlipOutReport& report, const std::string& accept);

/// Makes the curves edges of st and marks them: Bézier curves first (each with the earlier ones
/// fixed), then the paths and loops through their vertices (pinned at each), shortened together by
/// FlipOut with the Bézier curves fixed. Curves may meet and cross at vertices; they may not share
/// an edge.
/// Before any flip, check_curve_budget(st.intrinsic(), specs, max_memory_bytes). Messages name
/// input vertex ids only (vertices a Bézier curve inserted are called so).
/// @throws InvalidInput naming the curve (by index) on bad vertices (out of range, fewer than 2,
///         consecutive repeats, on different components), bad rounds, a Bézier curve over the
///         budget, or two curves sharing an edge (naming both); on a curve FlipOut leaves not
///         made of consecutive edges
CurveNetwork insert_curves(SignpostTriangulation& st, const std::vector<CurveSpec>& specs,
                           const FlipOutOptions& options = {}, double max_memory_bytes = 0.0);

/// The vertices of curve c in order along it (#edges + 1 for an open curve, the first repeated at
/// the end of a loop), with the arc length at each, and for each edge the halfedge running along
/// the curve (its face is on the curve's left; kInvalidIndex where the curve runs against a
/// boundary side, which has no left face).
struct CurveChain {
  std::vector<Index> vertices;
  std::vector<double> arclength;
  std::vector<Index> left_halfedges;  ///< #edges
  std::vector<Index> edges;           ///< #edges
};
/// @throws InvalidInput if c is out of range
CurveChain curve_chain(const IntrinsicTriangulation& tri, const CurveNetwork& net, Index c);

/// Flips st to the constrained intrinsic Delaunay triangulation: every non-Delaunay edge that is
/// not constrained, until none is left (constrained non-Delaunay edges are counted as
/// unflippable in the report).
FlipReport flip_to_constrained_delaunay(SignpostTriangulation& st, const CurveNetwork& net);

/// Signs of the cotan weights (w_ij = (cot α + cot β) / 2 per edge) of a triangulation.
struct CotanSigns {
  Index negative_constrained = 0;    ///< constrained edges with w < 0 (allowed: not Delaunay)
  Index negative_unconstrained = 0;  ///< other edges with w < 0 (0 on a constrained Delaunay
                                     ///< triangulation, up to rounding)
  double min_weight = 0.0;           ///< smallest w over all edges
};
/// Counts them; weights below −1e-12 · (the edge's largest |cot|) count as negative.
CotanSigns cotan_signs(const IntrinsicTriangulation& tri, const std::vector<char>& constrained);

}  // namespace ifem::intrinsic
