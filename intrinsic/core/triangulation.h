// The intrinsic triangulation: a Δ-complex (faces glued along sides) plus one length per edge.
// Representation: the gluing map of Sharp & Crane 2020 ("A Laplacian for Nonmanifold Triangle
// Meshes", §4.1). Halfedge h = 3*f + s is side s of face f, running from corner s to corner s+1.
#pragma once

#include <functional>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/types.h"

namespace ifem::intrinsic {

/// What construction repaired, counted (never silently).
struct BuildReport {
  Index input_faces = 0;            ///< faces given
  Index dropped_faces = 0;          ///< faces that repeat a vertex index (dropped)
  Index reoriented_faces = 0;       ///< faces whose corner order was reversed so that the
                                    ///< gluing is orientable (orientable but inconsistent input)
  Index unreferenced_vertices = 0;  ///< vertices no kept face uses (kept, with no halfedges)
  std::vector<Index> face_origin;   ///< for each triangulation face, the input face it came from
};

/// The mollification margin used everywhere unless a caller asks otherwise: every triangle is
/// made to satisfy a + b − c ≥ kDefaultMollifyEpsilon × (robust mean edge length,
/// robust_mean_length in triangle_formulas.h) (Sharp & Crane 2020).
inline constexpr double kDefaultMollifyEpsilon = 1e-5;

/// Outcome of mollify(): the uniform length increment that was added to every edge.
struct MollifyReport {
  double epsilon = 0.0;  ///< the margin asked for, absolute (relative factor × mean length)
  double delta = 0.0;    ///< added to every edge length; 0 when nothing needed it
  Index faces_below_margin = 0;  ///< faces that violated a + b - c ≥ ε before mollification
};

/// Outcome of flip_to_delaunay().
struct FlipReport {
  std::size_t flips = 0;        ///< edge flips performed
  std::size_t unflippable = 0;  ///< non-Delaunay edges that could not be flipped
  bool hit_flip_cap = false;    ///< true if the safety cap on flips was reached
};

class IntrinsicTriangulation;

/// The 2D layout of face f used by every direction in this library: corner 0 at the origin,
/// corner 1 on the positive x axis, corner 2 above it (from the three side lengths).
void face_layout(const IntrinsicTriangulation& tri, Index f, Eigen::Vector2d p[3]);

/// An intrinsic triangulation: connectivity (a Δ-complex, self-edges and repeated vertices
/// allowed, boundary allowed) and one length per edge. No positions.
///
/// Vertex ids 0..n_vertices()-1 are the caller's vertex ids (unreferenced vertices included).
/// Connectivity and lengths live in one object so a flip never leaves them out of sync.
class IntrinsicTriangulation {
 public:
  IntrinsicTriangulation() = default;

  // ===== Construction =====

  /// Builds from triangles and vertex positions (lengths = Euclidean distances).
  /// Faces that repeat a vertex are dropped; an orientable but inconsistently oriented input
  /// is reoriented; both are counted in `report`.
  /// @param faces #F triangles over vertex ids in [0, positions.rows())
  /// @param positions #V×3, finite
  /// @throws InvalidInput on an index out of range or a non-finite coordinate
  /// @throws NonManifoldInput on an edge with 3+ faces or a non-orientable gluing, naming it
  static IntrinsicTriangulation from_positions(const std::vector<Triangle>& faces,
                                               const Positions& positions,
                                               BuildReport* report = nullptr);

  /// Builds from triangles and per-side lengths: side_lengths(f, s) is the length of the side
  /// from corner s to corner s+1 of face f. Sides glued together must agree (1e-12 relative).
  /// @throws InvalidInput on a negative / non-finite length or glued sides that disagree
  /// @throws NonManifoldInput as from_positions()
  static IntrinsicTriangulation from_side_lengths(const std::vector<Triangle>& faces,
                                                  Index n_vertices,
                                                  const Eigen::MatrixX3d& side_lengths,
                                                  BuildReport* report = nullptr);

  /// Builds directly from a gluing map (used by the tufted cover).
  /// @param tail #H = 3F vertex ids, tail[3f+s] = corner s of face f
  /// @param twin #H involution without fixed points, or kInvalidIndex on boundary sides; a
  ///        glued pair must run in opposite directions (tail[h] == tail[next(twin[h])])
  /// @param halfedge_length #H lengths; glued sides must agree exactly
  /// @param multiplicity how many times each point of the input surface is covered (2 for the
  ///        tufted cover); operators divide by it
  /// @throws InvalidInput if the arrays do not form a valid Δ-complex
  static IntrinsicTriangulation from_gluing(std::vector<Index> tail, std::vector<Index> twin,
                                            const std::vector<double>& halfedge_length,
                                            Index n_vertices, int multiplicity = 1);

  // ===== Sizes =====
  Index n_vertices() const { return n_vertices_; }
  Index n_faces() const { return static_cast<Index>(tail_.size() / 3); }
  Index n_halfedges() const { return static_cast<Index>(tail_.size()); }
  Index n_edges() const { return static_cast<Index>(length_.size()); }

  // ===== Combinatorics (face-side halfedges: face and next are arithmetic) =====
  static Index face(Index h) { return h / 3; }
  static Index side(Index h) { return h % 3; }
  static Index next(Index h) { return h % 3 == 2 ? h - 2 : h + 1; }
  static Index prev(Index h) { return h % 3 == 0 ? h + 2 : h - 1; }
  static Index halfedge(Index f, Index s) { return 3 * f + s; }

  /// The side glued to h, or kInvalidIndex if h is on the boundary.
  Index twin(Index h) const { return twin_[h]; }
  /// Vertex at the start of h.
  Index tail(Index h) const { return tail_[h]; }
  /// Vertex at the end of h.
  Index head(Index h) const { return tail_[next(h)]; }
  /// Edge of h.
  Index edge(Index h) const { return edge_[h]; }
  /// One halfedge of edge e; on a boundary edge, its only halfedge.
  Index edge_halfedge(Index e) const { return edge_halfedge_[e]; }
  /// One outgoing halfedge of v (on a boundary vertex, one whose twin is invalid);
  /// kInvalidIndex for an unreferenced vertex.
  Index vertex_halfedge(Index v) const { return vertex_halfedge_[v]; }
  bool is_boundary_edge(Index e) const { return twin_[edge_halfedge_[e]] == kInvalidIndex; }
  bool has_boundary() const;

  // ===== Geometry (lengths only; derived quantities are free functions in geometry.h) =====
  double length(Index e) const { return length_[e]; }
  double halfedge_length(Index h) const { return length_[edge_[h]]; }
  const std::vector<double>& lengths() const { return length_; }
  /// 1 for an ordinary triangulation, 2 for a tufted cover (every face appears twice).
  int multiplicity() const { return multiplicity_; }

  /// Raw arrays (read-only), for fast loops.
  const std::vector<Index>& tails() const { return tail_; }
  const std::vector<Index>& twins() const { return twin_; }
  const std::vector<Index>& edges() const { return edge_; }

  // ===== Intrinsic Delaunay =====

  /// True if the interior edge e satisfies α + β ≤ π (1 + 1e-13) for its opposite angles;
  /// boundary edges are always Delaunay. A NaN length makes an edge count as Delaunay, so
  /// flipping can never loop on bad data.
  bool is_delaunay(Index e) const;

  /// Flips edge e in O(1): its diamond's other diagonal, with the length from the diamond's
  /// 2D layout. Returns false (and changes nothing) on a boundary edge, an edge whose two
  /// sides lie in one face, or an edge whose diamond is not strictly convex. Every
  /// non-Delaunay edge of a triangulation with positive face areas is flippable.
  bool flip_edge(Index e);

  /// Every entry one flip_edge() writes, as it was before the flip (the diamond's six halfedges,
  /// the outer partners of its four sides, their edges, its corners, the flipped edge's length).
  struct FlipUndo {
    Index edge = kInvalidIndex;  ///< the flipped edge
    double length = 0.0;
    int n_halfedges = 0;
    Index halfedge[10], tail[10], twin[10], edge_of[10];
    Index side_edge[4], side_edge_halfedge[4];
    Index vertex[4], vertex_halfedge[4];
  };
  /// flip_edge(e), filling *undo (when the flip happens) so that undo_flip(*undo) restores the
  /// triangulation bit for bit (gluing, edge ids, lengths).
  bool flip_edge(Index e, FlipUndo* undo);
  /// Undoes the flip `undo` was filled by. Precondition: every later flip is undone first.
  void undo_flip(const FlipUndo& undo);

  /// Flips non-Delaunay edges until every edge is Delaunay. Terminates on every input
  /// (tolerance, NaN-safe test, and a cap of 50·E + 1000 flips that is reported if reached).
  FlipReport flip_to_delaunay();

  /// Same queue and stopping rules, with `flip(e)` doing each flip (it must flip e in this
  /// triangulation or return false): lets a structure layered on top (signposts) update its own
  /// data per flip without repeating the algorithm.
  FlipReport flip_to_delaunay(const std::function<bool(Index)>& flip);

  /// Local Delaunay repair (after an insertion): flips non-Delaunay edges reachable from the
  /// edges in `queue` (taken last first), queueing the four outer sides of every flipped
  /// diamond, until none is left or the cap of 50·E + 1000 flips (reported) is reached.
  /// Appends the two faces of every flip to `touched` when given (with repeats).
  FlipReport flip_to_delaunay_from(std::vector<Index> queue, std::vector<Index>* touched);

  /// Same, with `flip(e)` doing each flip (as flip_to_delaunay(flip)).
  FlipReport flip_to_delaunay_from(std::vector<Index> queue, std::vector<Index>* touched,
                                   const std::function<bool(Index)>& flip);

  /// Adds the smallest uniform δ ≥ 0 to every edge length so that every face satisfies
  /// a + b − c ≥ ε for all three orderings, ε = relative_epsilon × robust_mean_length(edge lengths)
  /// (the mean of the lengths up to kOutlierClip × their 99th percentile: one far outlier vertex
  /// does not inflate every triangle's margin)
  /// (Sharp & Crane 2020, §4.5). Geometry unchanged when no face is below the margin.
  MollifyReport mollify(double relative_epsilon = kDefaultMollifyEpsilon);

  // ===== Insertion (defined in triangulation_insert.cpp; insertions append) =====

  /// Inserts a new vertex (id n_vertices()) inside face f, at distances l0, l1, l2 from
  /// corners 0, 1, 2 of f; returns its id. O(1). Slots, with f = (c0, c1, c2) and new faces
  /// f1 = n_faces() and f2 = n_faces() + 1 (before the call):
  ///   face f  = (c0, c1, v): 3f   c0→c1 (unchanged), 3f+1  c1→v, 3f+2  v→c0
  ///   face f1 = (c1, c2, v): 3f1  c1→c2 (old 3f+1),  3f1+1 c2→v, 3f1+2 v→c1
  ///   face f2 = (c2, c0, v): 3f2  c2→c0 (old 3f+2),  3f2+1 c0→v, 3f2+2 v→c2
  /// New edges (n_edges() before the call, in this order): v–c0, v–c1, v–c2.
  /// The caller is responsible for the lengths describing a point inside f.
  Index insert_vertex_in_face(Index f, double l0, double l1, double l2);

  /// Inserts a new vertex inside face f at barycentric coordinates `bary` (for corners 0, 1, 2;
  /// all > 0, summing to 1): the three new lengths are the distances in f's 2D layout
  /// (face_layout()). Same slots and ids as above; returns the new vertex id.
  Index insert_vertex_in_face(Index f, const Eigen::Vector3d& bary);

  /// Splits edge e at a new vertex m (id n_vertices()), at distance `t`·length(e) from the
  /// tail a of h = edge_halfedge(e); returns m. O(1). With face(h) = (a, b, c) (h, h1, h2) and,
  /// if e is interior, face(t) = (b, a, d) (tw, t1, t2), new faces g1 = n_faces(), g2 = g1 + 1:
  ///   face(h)  = (a, m, c): h  a→m (edge e), h1 m→c (new edge), h2 c→a (unchanged)
  ///   face g1  = (m, b, c): 3g1 m→b, 3g1+1 b→c (old h1), 3g1+2 c→m
  ///   face(tw) = (b, m, d): tw b→m, t1 m→d (new edge), t2 d→b (unchanged)
  ///   face g2  = (m, a, d): 3g2 m→a, 3g2+1 a→d (old t1), 3g2+2 d→m
  /// On a boundary edge only face(h) and g1 exist (3g1 is then a boundary side). New edges,
  /// in order: m–b, m–c, then (interior only) m–d. l_mc / l_md are the new diagonals.
  /// @throws InvalidInput if e is out of range or !can_split_edge(e) (ask first)
  Index split_edge(Index e, double t, double l_mc, double l_md);

  /// True when split_edge(e, ...) can split edge e: false for an edge whose two sides lie in
  /// one face (a self-glued side), the one layout the O(1) rewrite does not handle.
  /// Precondition: e in [0, n_edges()).
  bool can_split_edge(Index e) const {
    const Index h = edge_halfedge_[e];
    return twin_[h] == kInvalidIndex || face(twin_[h]) != face(h);
  }

  /// Splits edge e at fraction t ∈ (0, 1) as above, with the new diagonals l_mc / l_md
  /// measured in the 2D layouts of the one or two faces of e (boundary edges included).
  Index split_edge(Index e, double t);

  /// Sets the length of edge e (used by callers that move inserted vertices).
  void set_length(Index e, double l) { length_[e] = l; }
  /// Renumbers the edges: edge e becomes the edge of halfedge edge_halfedge[e] (and its twin),
  /// with that halfedge as edge_halfedge(e); lengths follow their edges. Restores a saved edge
  /// numbering (the constructors number edges in halfedge order).
  /// @throws InvalidInput unless every halfedge belongs to exactly one listed edge
  void renumber_edges(const std::vector<Index>& edge_halfedge);

  /// Checks every structural invariant: twin is an involution without fixed points, glued
  /// sides run in opposite directions and share an edge, edge_halfedge and vertex_halfedge are
  /// consistent, lengths are finite and positive, every face satisfies the triangle inequality
  /// (to 1e-12 relative). Throws InvalidInput with a precise message on the first failure.
  void validate() const;

 private:
  // A local rewrite (flip, insertion, split) moves up to four halfedge slots' contents (edge
  // and gluing) to new slots. Record them before the rewrite, map stale slot ids with moved(),
  // then finish_slot_move() writes the contents at their new slots and re-points the outside
  // partners and edge_halfedge_ (partners inside the moved set are mapped too).
  struct SlotMove {
    int n = 0;
    Index old_slot[4], new_slot[4], old_twin[4], old_edge[4];
    Index moved(Index x) const {
      for (int k = 0; k < n; ++k) {
        if (x == old_slot[k]) return new_slot[k];
      }
      return x;
    }
  };
  SlotMove record_slot_move(int n, const Index* from, const Index* to) const;
  void save_diamond(Index e, FlipUndo* undo) const;
  // The flip loop of flip_to_delaunay() and flip_to_delaunay_from(): pops edges, flips the
  // non-Delaunay ones, pushes the diamond's sides (only those not queued when `queued` is given).
  // `known`, when given: a test already made per edge (1 Delaunay, 2 not, 0 none), used until a
  // flip changes the edge's diamond.
  FlipReport flip_stack(std::vector<Index>& stack, std::vector<char>* queued,
                        std::vector<char>* known, std::vector<Index>* touched,
                        const std::function<bool(Index)>& flip);
  void finish_slot_move(const SlotMove& m);

  void build_edges_and_vertices(const std::vector<double>& halfedge_length, bool check_agree);

  Index n_vertices_ = 0;
  int multiplicity_ = 1;
  std::vector<Index> tail_;             // #H
  std::vector<Index> twin_;             // #H
  std::vector<Index> edge_;             // #H
  std::vector<Index> edge_halfedge_;    // #E
  std::vector<Index> vertex_halfedge_;  // #V
  std::vector<double> length_;          // #E
};

}  // namespace ifem::intrinsic
