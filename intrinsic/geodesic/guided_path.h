// Start paths for FlipOut in the homotopy class of the shortest geodesic. FlipOut keeps the class
// of its start path around the vertices the path does not touch (a saddle vertex, total angle
// > 2π, can hold a geodesic on either side), so a Dijkstra edge path that passes such a vertex on
// the other side than the shortest geodesic ends as a longer geodesic. A guide potential φ ≈ the
// distance to the target (e.g. the heat method's, computed by the caller: this layer solves no
// linear systems) tells the side: the curve of steepest descent of φ runs beside the shortest
// geodesic, and an edge path along one side of the faces it crosses is in its class (no vertex
// lies between the two). With the exact distance (exact_distance.h) the curve is the shortest
// geodesic itself (exact_edge_path()): the same strip sides, from its traced path.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "intrinsic/geodesic/exact_distance.h"
#include "intrinsic/geodesic/flip_geodesic.h"

namespace ifem::intrinsic {

/// Which side of the crossed face strips descent_edge_path() runs along.
enum class StripSide {
  kShorter,  ///< per strip (between two vertices the curve touches), the shorter side
  kLeft,     ///< always the side on the curve's left (looking towards b)
  kRight,
};

/// An edge path from a to b homotopic to the steepest-descent curve of `guide` from a: the curve
/// follows −∇φ (φ linear on each face) across faces, and along an edge where the descent
/// directions of its two faces meet (a valley) or where it runs into the boundary, it goes to
/// that edge's lower end; from a vertex it leaves into the face whose corner holds −∇φ, or
/// along the steepest descending edge. The path runs along the side of each crossed face strip
/// (between two vertices the curve touches) that `side` picks; once a face has b as a corner, it
/// goes straight to b. Where the descent stalls (a vertex with no lower neighbour that is not b,
/// a vertex reached twice, more than 4·#F + 100 face crossings), it is the Dijkstra edge path
/// (shortest_edge_path) instead.
/// @param guide #V of tri: a potential decreasing towards b (≈ distance to b), finite on a's
///        component
/// @throws InvalidInput if a or b is out of range, a == b, guide has the wrong size, or b is not
///         reachable from a
EdgePath descent_edge_path(const IntrinsicTriangulation& tri, Index a, Index b,
                           const Eigen::VectorXd& guide, StripSide side = StripSide::kShorter);

/// An edge path from a to b in the class of the exact shortest geodesic from a to b
/// (from_b.path_to_source(a)): between two vertices the geodesic touches, the side of the strip
/// of faces it crosses that `side` picks (as descent_edge_path()). Where the traced points do
/// not form such strips (b not the path's source, an inconsistent trace), it is the Dijkstra edge
/// path (shortest_edge_path) instead. O(path length) after the exact distance.
/// @param from_b exact_distance(tri, {b}) on tri or an unflipped copy of it (its faces are the
///        strips'; the triangulation it was computed on must still exist, unchanged)
/// @throws InvalidInput if a or b is out of range, a == b, from_b was computed on a
///         triangulation of another size, or b is not reachable from a
EdgePath exact_edge_path(const IntrinsicTriangulation& tri, Index a, Index b,
                         const ExactDistance& from_b, StripSide side = StripSide::kShorter);

/// Which start paths shortest_geodesic() shortens (see ShortestGeodesicOptions::start).
enum class StartPath { kDijkstra, kGuided, kBest };

/// A readable name ("dijkstra", "guided", "best").
const char* to_string(StartPath start);
/// The StartPath named `name` (to_string()'s names: the CLI's --start, Python's start=).
/// @throws InvalidInput "'NAME': expected 'best', 'guided' or 'dijkstra'"
StartPath start_path_from(const std::string& name);

/// FlipOut on one open path without pinned joints, then a search over the neighbouring classes:
/// from the geodesic found, a start path that passes a vertex next to it (a corner of a face along
/// it, or one it runs through) on that vertex's other side, shortened on st and kept when shorter,
/// else its flips are undone (SignpostTriangulation::undo_flips()); repeated from each
/// improvement, at most `rounds` times. A trial costs its FlipOut plus O(#V + #E) of
/// bookkeeping; st ends holding the result's flips only.
FlipOutReport shorten_over_sides(SignpostTriangulation& st, EdgePath& path,
                                 const FlipOutOptions& options = {}, int rounds = 8);

/// How shortest_geodesic() searches.
struct ShortestGeodesicOptions {
  /// kDijkstra: FlipOut from the Dijkstra edge path only (no side search); kGuided: from the
  /// guided start paths (StripSide kShorter, kLeft, kRight; a → b down the guide to b and,
  /// reversed, b → a down the guide to a, for each guide given); kBest: those and the Dijkstra
  /// path. Every start but kDijkstra's is followed by shorten_over_sides(). Without a guide:
  /// kDijkstra.
  StartPath start = StartPath::kBest;
  int side_rounds = 8;  ///< shorten_over_sides() rounds, ≥ 0 (0: FlipOut only)
  FlipOutOptions flipout;
  /// @throws InvalidInput naming the field (side_rounds < 0, bad flipout options)
  void validate() const;
};

/// A geodesic from vertex a to vertex b that is the shortest one far more often than FlipOut from
/// one start path: every distinct start (see ShortestGeodesicOptions; a start equal to an
/// earlier one is skipped) is shortened on st, its flips undone afterwards, and the shortest
/// result's flips are redone at the end: st then holds exactly what shortening that start alone
/// gives (*path lives on it). No copy of st. Costs about #starts (≤ 7) × (FlipOut + the side
/// search's trials, each a FlipOut and O(#V + #E) of bookkeeping). A flip record the caller
/// opened (SignpostTriangulation::flip_journal_mark()) stays open and holds the result's flips.
/// @param guide_to_b nullptr, or #V of st.intrinsic(): ≈ the distance to b (descent_edge_path())
/// @param guide_to_a nullptr, or the same for a (its descent from b, reversed, is a start too:
///        the two descents differ, and where one ends in a longer class the other often does
///        not; docs/decisions.md D-124)
/// @param won nullptr, or set to the start the result came from (before its side search):
///        "shortest edge path" (the Dijkstra one), or "descent to b, S side" / "descent to a,
///        reversed, S side" with S the StripSide ("shorter", "left", "right")
/// @throws InvalidInput as shortest_edge_path(), on bad options or a guide of the wrong size
FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                const Eigen::VectorXd* guide_to_b,
                                const Eigen::VectorXd* guide_to_a,
                                const ShortestGeodesicOptions& options, EdgePath* path,
                                std::string* won = nullptr);

/// shortest_geodesic() with the exact distances to the end points, in this order until one
/// reaches the exact length exact_to_b.distance[a] (1e-12 relative; its side search stops there
/// too): the exact geodesic's strips (exact_edge_path(); shorter, left, right side) from a to b
/// and, reversed, from b to a (when exact_to_a is given); then (kBest) the Dijkstra edge path;
/// then the descent paths of the exact distances (descent_edge_path()). Each is followed by
/// shorten_over_sides(); the shortest result is kept. kDijkstra shortens the Dijkstra path only.
/// Same contract for st, *path and the flip record. Usually one start's search: the strips
/// reach the exact length on most pairs (docs/decisions.md D-200).
/// @param exact_to_b exact_distance(st.intrinsic(), {b}) on st as it is now (or on an unflipped
///        copy of it)
/// @param exact_to_a nullptr, or exact_distance(st.intrinsic(), {a})
/// @param won as shortest_geodesic(): "shortest edge path", "exact geodesic to b, S side",
///        "exact geodesic to a, reversed, S side", "descent to b, S side" or "descent to a,
///        reversed, S side" (S: "shorter", "left", "right")
/// @throws InvalidInput as shortest_geodesic() and exact_edge_path()
FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                const ExactDistance& exact_to_b, const ExactDistance* exact_to_a,
                                const ShortestGeodesicOptions& options, EdgePath* path,
                                std::string* won = nullptr);

/// Same, with the exact distance to a asked for only when a start needs it: `exact_to_a` is
/// called at most once, after the first start (the strip to b, shorter side) fell short of the
/// exact length, with st as it was at the call (that start's flips undone); it returns nullptr
/// (then only the starts toward b are tried) or exact_distance(st.intrinsic(), {a}), which must
/// live until this returns. Same starts in the same order as with the distance given up front,
/// so the same result (docs/decisions.md D-206).
FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                const ExactDistance& exact_to_b,
                                const std::function<const ExactDistance*()>& exact_to_a,
                                const ShortestGeodesicOptions& options, EdgePath* path,
                                std::string* won = nullptr);

/// The first form with exact_to_a = nullptr (a literal nullptr would fit both forms above).
inline FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                       const ExactDistance& exact_to_b, std::nullptr_t,
                                       const ShortestGeodesicOptions& options, EdgePath* path,
                                       std::string* won = nullptr) {
  const ExactDistance* none = nullptr;
  return shortest_geodesic(st, a, b, exact_to_b, none, options, path, won);
}

}  // namespace ifem::intrinsic
