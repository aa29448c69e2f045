// Geodesic paths by edge flips: FlipOut (Sharp & Crane 2020, "You Can Find Geodesic Paths in
// Triangle Meshes by Just Flipping Edges"). A path made of intrinsic edges is shortened by
// flipping the edges inside a wedge where it bends by less than π, until it can be rerouted
// along the wedge's outer boundary; at convergence every wedge angle at an interior path vertex
// is ≥ π − ε on both sides, so the path is a locally shortest (geodesic) path on the surface.
// All flips go through SignpostTriangulation::flip_edge, so the path can be traced over the
// input mesh afterwards.
#pragma once

#include <Eigen/Core>
#include <vector>

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

/// An open path along intrinsic edges: steps[i] ends where steps[i+1] starts (by halfedge
/// identity, so self-edges and repeated vertices are fine). Empty: a single vertex.
struct EdgePath {
  std::vector<PathStep> steps;
};

/// The halfedge that traverses `step` in its direction, or kInvalidIndex when it runs against a
/// boundary side (that side has no twin).
Index step_halfedge(const IntrinsicTriangulation& tri, const PathStep& step);
/// The vertex a step starts at / ends at.
Index step_tail(const IntrinsicTriangulation& tri, const PathStep& step);
Index step_head(const IntrinsicTriangulation& tri, const PathStep& step);

/// Sum of the intrinsic lengths of the path's steps (length unit of tri).
double path_length(const IntrinsicTriangulation& tri, const EdgePath& path);

/// A shortest path from vertex a to vertex b along intrinsic edges (Dijkstra on edge lengths).
/// @throws InvalidInput if a or b is out of range, a == b, or b is not reachable from a (they
///         lie on different connected components)
EdgePath shortest_edge_path(const SignpostTriangulation& st, Index a, Index b);

/// The two wedge angles at the vertex between steps[i − 1] and steps[i] (1 ≤ i < #steps): the
/// angle swept counter-clockwise from the outgoing step to the reversed incoming one ([0]) and
/// from the reversed incoming step to the outgoing one ([1]), each a sum of corner angles
/// (radians); together they make the vertex's total angle. A wedge that would sweep over the
/// boundary is +∞: at a boundary vertex only the wedge on the interior side counts (a path may
/// hug the boundary). Both are 0 at a backtrack (steps i − 1 and i: one edge, both ways).
Eigen::Vector2d wedge_angles(const IntrinsicTriangulation& tri, const EdgePath& path, Index i);

/// The smallest wedge angle over all interior path vertices (+∞ if there is none).
double min_wedge_angle(const IntrinsicTriangulation& tri, const EdgePath& path);

/// How shorten() runs.
struct FlipOutOptions {
  /// Converged when every wedge angle at an interior path vertex is ≥ π − angle_epsilon
  /// (radians, in [0, π)). At a boundary vertex only the wedge not containing the boundary is
  /// straightened (wedge_angles()).
  double angle_epsilon = 1e-6;
  /// At most this many reroutes (FlipOut steps); −1: 10 × #E + 1000.
  Index max_iterations = -1;
  /// Stop when a reroute shortens the path by less than this fraction of its length (≥ 0).
  double min_relative_decrease = 1e-12;
  /// @throws InvalidInput naming the field on a value outside its range
  void validate() const;
};

/// Why shorten() stopped.
enum class FlipOutStop {
  kConverged,     ///< all wedge angles ≥ π − ε
  kIterationCap,  ///< max_iterations reroutes done
  kNoProgress,    ///< a reroute gained too little, or every bent wedge was blocked (its
                  ///< interior edges belong to the path or cannot be flipped)
};

/// What shorten() did.
struct FlipOutReport {
  double initial_length = 0.0;
  double final_length = 0.0;
  Index flips = 0;       ///< edge flips performed
  Index iterations = 0;  ///< reroutes performed
  FlipOutStop stopped_by = FlipOutStop::kConverged;
};

/// Shortens `path` (an open edge path of st.intrinsic()) by FlipOut, always at the currently
/// smallest wedge angle first. Flips edges of st (the surface is unchanged; the triangulation
/// and signposts change); the path's endpoints stay fixed and its length never increases.
/// @throws InvalidInput on bad options or a path whose steps are not consecutive
FlipOutReport shorten(SignpostTriangulation& st, EdgePath& path,
                      const FlipOutOptions& options = {});

/// The path as a polyline of 3D points on the input surface: every step traced over the input
/// with the signposts (SignpostTriangulation::trace_halfedge), joints shared. Its 3D length
/// equals path_length() up to tracing round-off (and the mollification, if any).
/// @throws TraceError when a step cannot be traced
std::vector<Eigen::Vector3d> path_polyline(const SignpostTriangulation& st, const EdgePath& path);

}  // namespace ifem::intrinsic
