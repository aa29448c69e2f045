// Integer coordinates for intrinsic triangulations (Gillespie, Sharp & Crane 2021, "Integer
// Coordinates for Intrinsic Geometry Processing"): a second way, besides signposts, to keep the
// correspondence between an intrinsic triangulation and the input mesh it lives on.
//
// Per intrinsic edge e, the normal coordinate n(e) counts the input edges that cross e
// transversally; n(e) = −1 means e runs along (a piece of) an input edge. Per intrinsic
// halfedge h leaving a vertex v that input edges leave ("spokes", see below), the roundabout
// r(h) is the index, in v's counter-clockwise list of spokes, of the first spoke met turning
// counter-clockwise from h (h's own spoke when h runs along one). Flips update both with
// integer formulas only; insertions and edge splits measure where the new edges fall among the
// input edges of the one or two faces they cut (floating point only for positions along edges).
// docs/decisions.md D-190..D-192, D-240.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

/// One input edge crossing an intrinsic halfedge (NormalCoordinateTriangulation::trace_halfedge).
struct InputCrossing {
  Index input_edge = kInvalidIndex;  ///< edge of input() crossed
  double t = 0.0;  ///< where, as a fraction of the intrinsic halfedge from its tail, in (0, 1)
  double input_t = 0.0;  ///< where, as a fraction of input().edge_halfedge(input_edge) from its
                         ///< tail, in (0, 1)
  /// true when the input edge, run from its tail to its head, crosses the intrinsic halfedge
  /// from right to left (into the halfedge's face). From the integers (which ends of the input
  /// edge the two halves of the crossing arc reach), so exact where input_t and t are not: at
  /// a crossing within rounding of an intrinsic vertex.
  bool into_left = true;
};

/// A spoke: one direction in which an input edge leaves an intrinsic vertex. Input vertices
/// have one per incident input edge end (a self-loop gives two); a vertex inserted on an input
/// edge (split_edge of an edge with n = −1, or insert_vertex within rounding of an input edge
/// crossing the face) has two, one per direction along it; any other inserted vertex has none.
struct InputSpoke {
  Index input_edge = kInvalidIndex;  ///< edge of input()
  double at = 0.0;  ///< the vertex's position along input().edge_halfedge(input_edge), as a
                    ///< fraction from its tail (0 or 1 at input vertices)
};

/// An intrinsic triangulation with normal coordinates and roundabouts, over an input mesh kept
/// alongside. Every operation goes through IntrinsicTriangulation's own flip / insertion /
/// split with the same arguments, so its geometry (edge lengths, edge and halfedge ids) is
/// exactly that of a SignpostTriangulation driven by the same calls.
class NormalCoordinateTriangulation {
 public:
  /// Builds the input triangulation (as IntrinsicTriangulation::from_positions) and starts the
  /// intrinsic triangulation as a copy of it: every n(e) = −1. A vertex may have several fans
  /// of faces (spokes are listed fan after fan).
  /// @param mollify_relative_epsilon if > 0, both triangulations are mollified with this margin
  ///        (IntrinsicTriangulation::mollify), as SignpostTriangulation does
  /// @throws InvalidInput / NonManifoldInput as IntrinsicTriangulation::from_positions
  NormalCoordinateTriangulation(const std::vector<Triangle>& faces, const Positions& positions,
                                double mollify_relative_epsilon = 0.0,
                                BuildReport* report = nullptr);

  // ===== Access =====
  const IntrinsicTriangulation& intrinsic() const { return tri_; }
  const IntrinsicTriangulation& input() const { return input_; }
  const Positions& input_positions() const { return positions_; }
  Index n_input_vertices() const { return input_.n_vertices(); }
  /// For each face of input(), the index of the given face it came from.
  const std::vector<Index>& input_face_origin() const { return face_origin_; }
  /// n(e): input edges crossing intrinsic edge e, or −1 if e runs along an input edge.
  int normal_coordinate(Index e) const { return n_[e]; }
  /// r(h) in [0, #spokes(tail(h))), 0 at a vertex without spokes.
  int roundabout(Index h) const { return r_[h]; }
  /// The spokes of intrinsic vertex v, counter-clockwise (on the boundary, starting along the
  /// outgoing boundary side; a vertex with several fans of faces lists them one after another).
  const std::vector<InputSpoke>& spokes(Index v) const { return spokes_[v]; }
  /// The index of the spoke `steps` counter-clockwise from spoke r of vertex v, within the fan
  /// of faces spoke r belongs to (indices wrap within a closed fan); 0 at a vertex without
  /// spokes. Precondition: r < spokes(v).size() when v has spokes.
  int spoke_index(Index v, int r, long steps) const;
  /// The input edge intrinsic halfedge h runs along (n = −1), else kInvalidIndex.
  Index input_edge_along(Index h) const;
  /// The position of vertex v along input().edge_halfedge(input_edge), as a fraction from its
  /// tail. Precondition: v lies on that input edge (an end of it, or a vertex inserted on it).
  double vertex_at(Index v, Index input_edge) const;

  // ===== Operations (all keep the normal coordinates and roundabouts up to date) =====

  /// IntrinsicTriangulation::flip_edge, with the integer update. O(1).
  bool flip_edge(Index e);
  /// IntrinsicTriangulation::flip_to_delaunay through flip_edge().
  FlipReport flip_to_delaunay();
  /// IntrinsicTriangulation::flip_to_delaunay_from through flip_edge() (local repair after an
  /// insertion); appends every face a flip touched to `touched` when given.
  FlipReport flip_to_delaunay_from(std::vector<Index> queue, std::vector<Index>* touched);
  /// The same two, never flipping an edge e whose fixed_edges[e] is nonzero (entries past the
  /// end count as 0): constrained edges stay (counted as unflippable when not Delaunay).
  FlipReport flip_to_delaunay(const std::vector<char>& fixed_edges);
  FlipReport flip_to_delaunay_from(std::vector<Index> queue, std::vector<Index>* touched,
                                   const std::vector<char>& fixed_edges);
  /// Inserts a vertex in intrinsic face f at barycentric coordinates `bary` (all > 0), as
  /// IntrinsicTriangulation::insert_vertex_in_face(f, bary); returns its id. A point within
  /// rounding of an input edge crossing f (1e-10 of f's longest side, in f's layout; the
  /// nearest such edge) is taken to lie on it: the vertex gets two spokes and the edge ends at
  /// it, so every later count agrees on that side (an exactly symmetric input puts
  /// circumcenters on its symmetry axis). Traces f's three sides (O(their crossings × the
  /// length of the crossing input edges in faces)).
  Index insert_vertex(Index f, const Eigen::Vector3d& bary);
  /// Splits intrinsic edge e at fraction t ∈ (0, 1) from the tail of edge_halfedge(e), as
  /// IntrinsicTriangulation::split_edge(e, t) (boundary edges included); returns the new vertex.
  /// A vertex on an input edge (n(e) = −1, or t within 1e-10 of where an input edge crosses e;
  /// the nearest such crossing) gets two spokes, and that input edge ends at it.
  /// @throws InvalidInput as IntrinsicTriangulation::split_edge
  Index split_edge(Index e, double t);

  // ===== Moving inserted vertices (relax_inserted_vertices(), intrinsic/refine/delaunay_refine.h)

  /// Whether a side without twin starts or ends at vertex v (walks the fan of faces at
  /// vertex_halfedge(v): every fan for a vertex with one, as inserted vertices).
  bool is_boundary_vertex(Index v) const;
  /// Moves inserted interior vertex v by `displacement`, given in the layout of
  /// inserted_vertex_star(intrinsic(), v, n_input_vertices(), …) (intrinsic/core/geometry.h),
  /// as SignpostTriangulation::move_inserted_vertex (the same checks, check_star_move()): the
  /// star keeps its edges and ids, the spokes get their new planar lengths. The input edges
  /// crossing the star are straight chords of its flat layout; which ring vertex or outer crossing
  /// each chord joins comes from the integers, and only which side of each chord the new position
  /// lies on from floating point. From those, the spokes' normal coordinates and the roundabouts of
  /// the ring vertices towards v are recounted (the outer sides keep theirs). A vertex on an input
  /// edge leaves it: its spokes are dropped and the input edge becomes one more chord. Returns
  /// false and changes nothing if v has no such star, if the new position is not strictly
  /// inside the star's kernel (as SignpostTriangulation::move_inserted_vertex with
  /// min_relative_height), or if two chords pass within 1e-10 of the star's radius of it
  /// (which sides it lies on could then disagree with each other). O(star sides + chords ×
  /// star sides), plus tracing the outer sides (trace_halfedge()).
  /// @throws InvalidInput if the coordinates are inconsistent (a bug, or a broken invariant)
  bool move_inserted_vertex(Index v, const Eigen::Vector2d& displacement,
                            double min_relative_height = 1e-6);

  // ===== Tracing from the integers =====

  /// The input edges crossing intrinsic halfedge h, in order from its tail (n(edge(h)) of them;
  /// none when n ≤ 0). Each is found by following its arcs through the intrinsic faces to the
  /// vertices it leaves (roundabouts name it), and placed by laying those faces out in the
  /// plane (where the arc runs along h, both within rounding of each other, at a point of h
  /// within rounding of the arc: t and input_t stay within their segments). Does not build the
  /// common subdivision.
  /// @throws InvalidInput if the coordinates are inconsistent (a bug, or a broken invariant)
  std::vector<InputCrossing> trace_halfedge(Index h) const;
  /// trace_halfedge(intrinsic().edge_halfedge(e)).
  std::vector<InputCrossing> trace_edge(Index e) const;
  /// A crossing as a point of the input surface (on the input edge's side of its face).
  SurfacePoint crossing_point(const InputCrossing& c) const;
  /// A crossing in 3D (on the straight input edge between its vertices' positions).
  Eigen::Vector3d crossing_position(const InputCrossing& c) const;
  /// The unit 3D direction in which intrinsic halfedge h leaves its tail, an input vertex, on
  /// the input surface: along the input edge it runs on (n = −1); towards its first crossing
  /// (n > 0); else (n = 0: h stays in the input face of its wedge, the one before spoke r(h))
  /// at the angle from that wedge's first spoke that the intrinsic corners give, walking
  /// clockwise from h to the first halfedge or input edge whose direction the integers fix (a
  /// spoke inside an intrinsic corner is placed by its crossing of the opposite side). The
  /// direction in the input face's layout is mapped affinely onto its 3D triangle, as
  /// SignpostTriangulation::halfedge_direction_3d() does. O(crossings traced).
  /// @throws InvalidInput if h is out of range or starts at an inserted vertex, or on
  ///         inconsistent coordinates
  Eigen::Vector3d halfedge_direction_3d(Index h) const;
  /// The angle at input vertex v = tail(h) from outgoing input halfedge `from` (of input(),
  /// tail v) counter-clockwise to the direction in which intrinsic halfedge h leaves v, in
  /// radians of the input's (mollified) corner angles: the sum of the input corners between
  /// `from` and the wedge h starts in, plus h's angle inside it (found as halfedge_direction_3d()
  /// finds it, without 3D). Negative when h lies clockwise of `from` in a fan that ends at the
  /// boundary before reaching h counter-clockwise. What SignpostTriangulation gives as
  /// halfedge_direction(h) − input_halfedge_direction(from) (modulo Θ_v inside).
  /// @throws InvalidInput if h is out of range, starts at an inserted vertex, `from` does not
  ///         start at v, h is not in the fan of faces of `from`, or on inconsistent coordinates
  double angle_from_input_halfedge(Index h, Index from) const;

  /// Checks the integer invariants: per face, the three coordinates admit normal arcs (even
  /// sums, at most one corner with arcs ending at it), roundabouts in range.
  /// @throws InvalidInput naming the first face or halfedge that fails
  void validate() const;

  // ===== Saving and restoring (format "ifem-integer 1", documented in normal_coordinates_io.cpp)

  /// Writes the input (positions, faces, gluing and lengths) and the intrinsic triangulation
  /// with its normal coordinates, roundabouts and spokes as text, doubles with 17 significant
  /// digits so that load() restores it bit for bit. Atomic (path.tmp, then rename).
  /// @throws IoError if the file cannot be written
  void save(const std::string& path) const;
  /// Reads a file written by save(); the result has the same lengths, ids, coordinates,
  /// roundabouts and spokes, and passes validate().
  /// @throws IoError naming the file and line on a missing, malformed, inconsistent or
  ///         unsupported-version file
  static NormalCoordinateTriangulation load(const std::string& path);

 private:
  struct FaceCounts {
    int n[3];       // max(n, 0) of sides 0, 1, 2
    int corner[3];  // arcs cutting off corner k (crossing sides k and k+2)
    int fan[3];     // arcs leaving corner k (crossing side k+1)
  };
  struct ArcEnd {
    Index vertex = kInvalidIndex;
    int spoke = 0;
    Eigen::Vector2d pos;
  };
  FaceCounts counts(Index f) const;
  double wedge_angle(Index h) const;
  Index spoke_out(Index v, int k) const;
  // An end of an input edge's piece inside the star of a vertex (move_inserted_vertex()):
  // a crossing of outer side `ring` (pos-th from ring vertex `ring`), ring vertex `ring`, or
  // the star's centre; at a vertex, the spoke it ends along when found by walk_star() (else −1).
  struct StarEnd {
    enum Kind { kOuter, kCorner, kCentre } kind = kOuter;
    int ring = 0, pos = 0, spoke = -1;
  };
  // A piece of an input edge across the star, between two ends, and one spoke it crosses
  // (ring index of that spoke's far end; −1 for the joined pieces at a vertex on an input edge).
  struct StarChord {
    std::array<StarEnd, 2> end;
    int crossed = -1;
  };
  StarEnd walk_star(const std::vector<Index>& spokes, Index h, int p, int* crossed) const;
  bool star_chords(Index v, const std::vector<Index>& spokes, std::vector<StarChord>* chords) const;
  bool shared(Index h) const { return n_[tri_.edge(h)] < 0; }
  ArcEnd follow(Index h, int p, Eigen::Vector2d a, Eigen::Vector2d b) const;
  // The arc of a face that a new vertex lies on within rounding (insert_vertex()): one of
  // corner `corner`'s corner arcs (cutting it off) or fan arcs (leaving it), `index`-th (from
  // 1, as counted along the sides); corner −1 when none. `spoke`: the input edge and the
  // vertex's place along it.
  struct OnArc {
    int corner = -1;
    bool fan = false;
    int index = 0;
    InputSpoke spoke;
  };
  OnArc arc_at(Index f, const Eigen::Vector3d& bary, const FaceCounts& c,
               const std::vector<InputCrossing> trace[3]) const;
  void count_new_spokes(Index f, const Eigen::Vector3d& bary, int crossing[3], int before[3],
                        OnArc* on) const;
  // The diagonal's crossings; `at_m`: the (q+1)-th crossing of the side is at the new vertex
  // (its arc, of kind 0 / 1 / 2 = corner arc of the side's tail / fan / corner arc of its head,
  // is not counted; a fan gives −1).
  int count_diagonal(Index side_h, int q, bool at_m, int* fan_before, int* kind) const;
  void grow_records();
  void add_fan(Index v, Index h0, std::vector<char>& seen);

  IntrinsicTriangulation input_;
  IntrinsicTriangulation tri_;
  Positions positions_;
  std::vector<Index> face_origin_;               // #F input: index into the faces given
  std::vector<int> n_;                           // #E intrinsic
  std::vector<int> r_;                           // #H intrinsic
  std::vector<std::vector<InputSpoke>> spokes_;  // #V intrinsic
  std::vector<std::vector<int>> fans_;  // #V: first spoke of each fan + end, for vertices with
                                        // several fans (empty otherwise)
};

}  // namespace ifem::intrinsic
