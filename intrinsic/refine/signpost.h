// Signpost intrinsic triangulations (Sharp, Soliman & Crane 2019, "Navigating Intrinsic
// Triangulations"): an intrinsic triangulation that also knows, for every halfedge, the
// direction it leaves its tail in, so each intrinsic edge can be traced over the input mesh
// as a straight (geodesic) path, and every inserted vertex knows where it sits on the input.
//
// Directions are angles measured counter-clockwise (in the orientation of the faces) at a
// vertex, in [0, Θ_v) with Θ_v the vertex's total angle (its angle sum on the input); as a
// polar coordinate they are scaled by 2π/Θ_v (π/Θ_v on the boundary). Angle 0 is the
// direction of a fixed outgoing halfedge, on the boundary the outgoing boundary halfedge, so a
// boundary vertex's directions fill [0, Θ_v].
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

/// Result of tracing a straight line over a triangulation (trace_straight()).
struct TraceResult {
  SurfacePoint end;                         ///< where the line ended
  Eigen::Vector2d direction;                ///< unit direction at the end, in end.face's layout
  bool hit_boundary = false;                ///< stopped at a boundary side (when not sliding) or
                                            ///< at a side of a stop edge (TraceOptions)
  Index boundary_halfedge = kInvalidIndex;  ///< the side it stopped at
  Index slides = 0;                         ///< times the line was slid along a boundary side
  std::vector<SurfacePoint> path;           ///< start, every side crossing, end (when recorded)
};

/// How trace_straight() runs.
struct TraceOptions {
  /// When the start is corner k of start.face (bary = e_k), k: the line may then first leave
  /// only through the side opposite k, never along a side at rounding level. −1: no such
  /// restriction. In {−1, 0, 1, 2}.
  int start_corner = -1;
  /// A line reaching a boundary side continues along it (a numerical fix for lines that run
  /// along the boundary); false: it stops there (TraceResult::hit_boundary).
  bool slide_on_boundary = false;
  /// Fill TraceResult::path.
  bool record_path = false;
  /// Give up (throw TraceError) after crossing this many sides; −1: 4 × #F + 1000.
  Index max_steps = -1;
  /// #E flags (may be shorter: missing entries are 0): the line stops at a side of a flagged
  /// edge as at a boundary side (hit_boundary, no sliding), e.g. at constrained edges.
  const std::vector<char>* stop_edges = nullptr;
  /// @throws InvalidInput naming the field: start_corner outside {−1, 0, 1, 2}, max_steps < −1
  void validate() const;
};

/// Traces the straight line leaving `start` (inside or on the boundary of start.face) in the
/// unit direction `dir` (start.face's layout, face_layout()) for `distance` (absolute, ≥ 0, in
/// the length unit of tri), unfolding across glued sides.
/// @throws InvalidInput on bad options
/// @throws TraceError if the line crosses more than max_steps sides (degenerate input)
inline TraceResult trace_straight(const IntrinsicTriangulation& tri, const SurfacePoint& start,
                                  const Eigen::Vector2d& dir, double distance,
                                  const TraceOptions& options = {});

/// Deprecated positional form of trace_straight(tri, start, dir, distance, TraceOptions) (same
/// meaning; max_steps has no −1 default here). The implementation until its definition in
/// signpost.cpp takes TraceOptions; call the TraceOptions form.
TraceResult trace_straight(const IntrinsicTriangulation& tri, const SurfacePoint& start,
                           Eigen::Vector2d dir, double distance, int start_corner,
                           bool slide_on_boundary, bool record_path, Index max_steps,
                           const std::vector<char>* stop_edges = nullptr);

inline TraceResult trace_straight(const IntrinsicTriangulation& tri, const SurfacePoint& start,
                                  const Eigen::Vector2d& dir, double distance,
                                  const TraceOptions& options) {
  options.validate();
  const Index max_steps = options.max_steps >= 0 ? options.max_steps : 4 * tri.n_faces() + 1000;
  return trace_straight(tri, start, dir, distance, options.start_corner, options.slide_on_boundary,
                        options.record_path, max_steps, options.stop_edges);
}

/// An intrinsic triangulation with signposts, over an input mesh kept alongside.
class SignpostTriangulation {
 public:
  /// Builds the input triangulation from faces and positions (faces repeating a vertex are
  /// dropped, orientation repaired, as IntrinsicTriangulation::from_positions) and starts the
  /// intrinsic triangulation as a copy of it.
  /// @param mollify_relative_epsilon if > 0, both triangulations are mollified with this margin
  ///        relative to the mean edge length (IntrinsicTriangulation::mollify; the input's
  ///        lengths are then the mollified ones; 3D output uses the positions)
  /// @throws InvalidInput / NonManifoldInput as IntrinsicTriangulation::from_positions
  SignpostTriangulation(const std::vector<Triangle>& faces, const Positions& positions,
                        double mollify_relative_epsilon = 0.0, BuildReport* report = nullptr);

  // ===== Saving and restoring (format "ifem-signpost 1", documented in signpost.cpp) =====

  /// Writes the input (positions, faces as given, mollification) and the intrinsic
  /// triangulation (gluing, lengths, signposts, vertex locations) to a text file, every double
  /// with 17 significant digits so that load() restores it bit for bit. Atomic (path.tmp, then
  /// rename). @throws IoError if the file cannot be written
  void save(const std::string& path) const;
  /// Reads a file written by save(): the input is rebuilt from its faces and positions (same
  /// repairs, same mollification), the intrinsic triangulation from its gluing. Halfedges,
  /// lengths, signposts, vertex locations and edge ids (with their edge_halfedge()) are
  /// identical to the saved ones (files without the optional 'edges' section get edges
  /// numbered in halfedge order). @throws IoError on a malformed file (naming the line)
  static SignpostTriangulation load(const std::string& path);

  // ===== Access =====
  const IntrinsicTriangulation& intrinsic() const { return tri_; }
  const IntrinsicTriangulation& input() const { return input_; }
  const Positions& input_positions() const { return positions_; }
  const MollifyReport& mollify_report() const { return mollify_; }
  /// The faces given to the constructor, as given (before dropping / reorienting).
  const std::vector<Triangle>& input_faces() const { return faces_; }
  /// For each face of input(), the index of the given face it came from.
  const std::vector<Index>& input_face_origin() const { return face_origin_; }
  /// The constructor's mollify_relative_epsilon (relative to the mean edge length).
  double mollify_epsilon() const { return mollify_epsilon_; }
  Index n_input_vertices() const { return input_.n_vertices(); }
  /// Θ_v, the total angle of intrinsic vertex v (2π at inserted interior vertices, π on the
  /// boundary).
  double vertex_angle_sum(Index v) const { return angle_sum_[v]; }
  bool is_boundary_vertex(Index v) const { return boundary_[v] != 0; }
  /// Signpost of intrinsic halfedge h: its direction at its tail, in [0, Θ_tail].
  double halfedge_direction(Index h) const { return direction_[h]; }
  /// Signpost of input halfedge h (of input()): its direction at its tail, in the same angular
  /// coordinate as the intrinsic signposts at that (input) vertex.
  double input_halfedge_direction(Index h) const { return input_direction_[h]; }
  /// Angle a as a signpost direction at intrinsic vertex v: modulo Θ_v into [0, Θ_v) at an
  /// interior vertex, clamped to [0, Θ_v] at a boundary vertex.
  double wrap_direction(Index v, double a) const { return wrap(v, a); }
  /// Where intrinsic vertex v lies on the input (an input face and barycentric coordinates).
  const SurfacePoint& vertex_location(Index v) const { return location_[v]; }
  /// 3D position of a point of the input surface.
  Eigen::Vector3d position(const SurfacePoint& p) const;
  /// 3D positions of all intrinsic vertices.
  Positions vertex_positions() const;
  /// Unit 3D direction in which intrinsic halfedge h leaves its tail over the input surface, in
  /// the plane of the input face where its straight line starts: at an input vertex the wedge of
  /// the input fan that holds its signpost (as trace_halfedge() starts), at an inserted vertex
  /// the face of its location. The face's layout is mapped affinely onto its 3D triangle: exact
  /// when the input was not mollified (else off by about the relative change of that face's
  /// lengths). No tracing: O(degree of the tail in the input).
  /// @throws InvalidInput if h is out of range or its tail has no input faces
  Eigen::Vector3d halfedge_direction_3d(Index h) const;

  // ===== Operations (all keep the signposts up to date) =====

  /// Flips intrinsic edge e (see IntrinsicTriangulation::flip_edge) and updates the
  /// signposts of the diamond in O(1).
  bool flip_edge(Index e);
  /// The same flip; when it happens and `corners` is not null, writes the two corner angles
  /// the signpost update measured: corners[0] = corner_angle(intrinsic(), next(twin(h))) and
  /// corners[1] = corner_angle(intrinsic(), next(h)), h = intrinsic().edge_halfedge(e) after
  /// the flip (the same bits corner_angle() gives; a caller caching corners saves two atan2).
  bool flip_edge(Index e, double* corners);
  /// Flips to intrinsic Delaunay, updating the signposts.
  FlipReport flip_to_delaunay();
  /// Flips non-Delaunay edges reachable from the queue of edges given (local repair after an
  /// insertion, IntrinsicTriangulation::flip_to_delaunay_from), updating the signposts;
  /// appends every face a flip touched to `touched` when given.
  FlipReport flip_to_delaunay_from(std::vector<Index> queue, std::vector<Index>* touched);
  /// The same two, never flipping an edge e whose fixed_edges[e] is nonzero (entries past the
  /// end count as 0): constrained edges stay (counted as unflippable when not Delaunay).
  FlipReport flip_to_delaunay(const std::vector<char>& fixed_edges);
  FlipReport flip_to_delaunay_from(std::vector<Index> queue, std::vector<Index>* touched,
                                   const std::vector<char>& fixed_edges);

  // ===== Undoing flips (e.g. trying several FlipOut start paths on one triangulation) =====

  /// Starts recording flips (every flip_edge(), also those of flip_to_delaunay*() and FlipOut)
  /// if not recording yet, and returns the number recorded so far: a mark for undo_flips().
  std::size_t flip_journal_mark();
  /// True between the first flip_journal_mark() and end_flip_journal().
  bool recording_flips() const { return recording_; }
  /// Undoes the flips recorded after `mark`, newest first: gluing, edge ids, lengths and
  /// signposts become bit for bit what they were at the mark (vertex locations never change
  /// by flips). O(flips undone). @throws InvalidInput if not recording or mark > recorded
  void undo_flips(std::size_t mark);
  /// The edges flipped after `mark`, in order: flipping them again in this order from the
  /// state at the mark gives the same triangulation (flips are deterministic).
  /// @throws InvalidInput as undo_flips()
  std::vector<Index> flips_since(std::size_t mark) const;
  /// Stops recording and forgets the record (the flips stay).
  void end_flip_journal();

  // ===== Operation log (replaying this triangulation's changes on another one) =====

  /// One change to the intrinsic triangulation that stays: a flip, an insertion in a face or
  /// an edge split, with the arguments it was made with.
  struct Operation {
    enum class Kind { kFlip, kInsertVertex, kSplitEdge };
    Kind kind = Kind::kFlip;
    Index index = kInvalidIndex;  ///< the edge flipped or split, or the face inserted in
    Eigen::Vector3d bary = Eigen::Vector3d::Zero();  ///< kInsertVertex: barycentric coordinates
    double t = 0.0;                                  ///< kSplitEdge: the fraction split at
  };
  /// Starts (or restarts, empty) logging every flip_edge() that happens (also those of
  /// flip_to_delaunay*() and FlipOut), insert_vertex() and split_edge(); undo_flips() removes
  /// the flips it undoes. Calling the same operations in the same order on a triangulation
  /// built from the same input (NormalCoordinateTriangulation) gives the same ids and lengths.
  /// move_inserted_vertex() is not logged.
  void start_operation_log();
  /// The operations since start_operation_log(), oldest first (empty when not logging).
  const std::vector<Operation>& operation_log() const { return op_log_; }
  /// Stops logging and forgets the log.
  void end_operation_log();

  /// Inserts a vertex in intrinsic face f at barycentric coordinates `bary` (all > 0) and
  /// locates it on the input; returns its id (n_vertices() before the call).
  /// @throws InvalidInput while recording flips (recording_flips())
  Index insert_vertex(Index f, const Eigen::Vector3d& bary);
  /// Splits intrinsic edge e at fraction t ∈ (0, 1) of its length from the tail of
  /// edge_halfedge(e) (boundary edges included); returns the new vertex id.
  /// @throws InvalidInput while recording flips (recording_flips())
  Index split_edge(Index e, double t);

  /// Moves inserted interior vertex v by `displacement`, given in the layout of
  /// inserted_vertex_star(intrinsic(), v, n_input_vertices(), …) (intrinsic/core/geometry.h;
  /// check_star_move() there makes the checks both representations share). The surface is unchanged
  /// (v moves inside its flat star): the spokes get their new planar lengths, the signposts at v
  /// and of the spokes' twins are updated (the ring vertices' total angles do not change), and v's
  /// location on the input is traced from the old one along the displacement. Returns false and
  /// changes nothing if v has no such star, if the new position is not strictly inside the star's
  /// kernel (every new triangle's height above its outer side at least min_relative_height × that
  /// side's length), or if the trace over the input fails.
  bool move_inserted_vertex(Index v, const Eigen::Vector2d& displacement,
                            double min_relative_height = 1e-6);

  /// Locates a point of the intrinsic triangulation on the input surface by tracing from a
  /// corner of f along the direction to it.
  SurfacePoint locate(Index f, const Eigen::Vector3d& bary) const;
  /// Traces intrinsic edge e over the input surface: a polyline of input surface points from
  /// one endpoint to the other (every input side crossed), starting at an endpoint that is an
  /// input vertex when there is one.
  /// @throws TraceError when tracing fails (too many crossings on a degenerate input)
  std::vector<SurfacePoint> trace_edge(Index e) const;
  /// Traces intrinsic halfedge h from its tail to its head: the segment between path[i] and
  /// path[i+1] lies in input face path[i].face (path[i+1] may be expressed in the next face).
  std::vector<SurfacePoint> trace_halfedge(Index h) const;
  /// Traces every intrinsic edge; polylines in 3D.
  std::vector<std::vector<Eigen::Vector3d>> traced_edges_3d() const;

  // ===== Function transfer =====

  /// Values on input vertices → intrinsic vertices: input vertices keep theirs, inserted ones
  /// interpolate linearly in their input face.
  Eigen::VectorXd input_to_intrinsic(const Eigen::VectorXd& input_values) const;
  /// Values on intrinsic vertices → input vertices (the first n_input_vertices() entries:
  /// input vertices are intrinsic vertices with the same ids).
  Eigen::VectorXd intrinsic_to_input(const Eigen::VectorXd& intrinsic_values) const;

 private:
  SignpostTriangulation() = default;
  void init_directions(const IntrinsicTriangulation& t, std::vector<double>& dir,
                       std::vector<double>& sum, std::vector<char>& boundary) const;
  double wrap(Index v, double a) const;
  void add_vertex_records();
  /// The outgoing input halfedge at input vertex v whose corner (wedge) holds direction phi.
  Index input_wedge(Index v, double phi) const;
  /// The unit direction alpha into the corner of input halfedge `wedge`, in its face's layout.
  Eigen::Vector2d wedge_direction(Index wedge, double alpha) const;
  /// Starts a trace over the input at intrinsic vertex v in signpost direction phi.
  TraceResult trace_from_vertex(Index v, double phi, double distance, bool record) const;
  /// Locates vertex v (just inserted) by tracing from neighbour u along halfedge h = u→v.
  void locate_from(Index h, Index v, double direction_v_to_u);

  IntrinsicTriangulation input_;
  IntrinsicTriangulation tri_;
  Positions positions_;
  std::vector<Triangle> faces_;     // as given
  std::vector<Index> face_origin_;  // #F input: index into faces_
  double mollify_epsilon_ = 0.0;
  MollifyReport mollify_;
  std::vector<double> input_direction_;  // #H input: signposts of the input halfedges
  std::vector<double> input_corner_;     // #H input: corner angle at each halfedge's tail
  std::vector<double> direction_;        // #H intrinsic
  std::vector<double> angle_sum_;        // #V intrinsic
  std::vector<char> boundary_;           // #V intrinsic
  std::vector<SurfacePoint> location_;   // #V intrinsic
  std::vector<double> frame_;            // #V: for inserted vertices, the angle (in the layout
                                         // of its location face) of signpost direction 0
  struct FlipRecord {
    IntrinsicTriangulation::FlipUndo tri;
    double direction[6];   // signposts of the diamond's halfedges h, t, next/prev of h, of t
    std::size_t log_size;  // operation_log().size() before the flip
  };
  bool logging_ = false;
  std::vector<Operation> op_log_;
  void log(Operation::Kind kind, Index index, const Eigen::Vector3d& bary, double t);
  bool recording_ = false;
  std::vector<FlipRecord> journal_;
  void check_not_recording(const char* what) const;
};

}  // namespace ifem::intrinsic
