// Intrinsic Delaunay refinement (Chew's second algorithm on an intrinsic triangulation, Sharp,
// Soliman & Crane 2019, §6.2): insert circumcenters of bad triangles, located by tracing over
// the intrinsic triangulation, until every triangle meets a minimum-angle bound. On signposts
// (inserted vertices located on the input) or on a bare Δ-complex such as the tufted cover.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "intrinsic/core/progress.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// What to refine towards.
struct RefineOptions {
  double min_angle_degrees = 25.0;  ///< minimum corner angle wanted, degrees, in (0, 30]
  /// Also split triangles whose area exceeds this (absolute, in squared length units; e.g.
  /// equilateral_area(ℓ) asks for edges of about ℓ). 0: no area bound. ≥ 0.
  double max_area = 0.0;
  /// cap on inserted vertices (−1: 10 × #input vertices + 2000, plus 4 × (faces' area /
  /// max_area) with an area bound: about four times the triangles that bound asks for); ≥ −1
  Index max_insertions = -1;
  /// Split boundary edges that face an obtuse angle (encroached: the opposite vertex lies in
  /// their diametral circle, Ruppert), until none is left. Chew's angle test alone keeps e.g.
  /// 25°-25°-130° triangles, whose boundary side gets a negative cotan weight; with this on,
  /// the refined Laplacian has non-negative weights on boundary edges too.
  bool split_encroached_boundary = true;
  /// Insert off-centers (Üngör 2004) instead of circumcenters for triangles with a small
  /// corner: the point on the way from the shortest side's midpoint to the circumcenter where
  /// the triangle on that side gets an apex angle just above the bound, when the circumcenter
  /// is farther. Same bound and termination argument. Fewer insertions on most meshes, more on
  /// meshes with rings of short sides, hence off by default (docs/decisions.md D-015).
  bool off_centers = false;
  /// With constraints: after the angle and size refinement, split constrained and boundary
  /// edges whose cotan weight is negative (opposite angles summing above π; on the boundary,
  /// one above π/2), at their midpoint or on concentric shells around a corner, until every
  /// cotan weight is ≥ 0 (conforming Delaunay refinement: the discrete maximum principle holds;
  /// details and what is not guaranteed in intrinsic/refine/conforming.h). Splits may lower
  /// the minimum angle (the report's min_angle_after). Without constraints: no effect.
  bool conform = true;
  /// Memory budget, bytes, for the refined triangulation and what is built on it (see
  /// estimate_refinement()): a request whose estimate exceeds it is refused before any work,
  /// and refinement stops (hit_insertion_cap) where the vertices would cost more than it.
  /// 0: default_memory_budget(); +∞: no budget. ≥ 0.
  double max_memory_bytes = 0.0;
  /// Progress, stage "refine": insertions made over estimate_refinement()'s insertions
  /// (saturating_fraction(): an underestimate slows the bar near its end instead of filling it),
  /// 1 when the refinement is done. Empty: none.
  ProgressCallback on_progress;
  /// @throws InvalidInput naming the field: min_angle_degrees outside (0, 30], max_area
  ///         negative or not finite, max_insertions < −1, max_memory_bytes negative or NaN
  void validate() const;
};

/// Edges that must stay edges of the triangulation (constraints: curves drawn on the surface).
/// Delaunay flips never flip them, and refinement never crosses them: a point that would land
/// across a constrained edge, or inside its diametral circle, splits that edge at its midpoint
/// instead (as boundary edges are split), and a constrained edge facing an obtuse angle is split
/// too (split_encroached_boundary), so the result is a constrained Delaunay triangulation. Then,
/// with RefineOptions::conform, constrained and boundary edges whose cotan weight is still
/// negative are split (intrinsic/refine/conforming.h), so every cotan weight is non-negative
/// except those counted in RefineReport::negative_barrier_weights (edges below the conforming
/// floor where constraints meet at tiny angles). Corners between two constrained (or boundary)
/// edges at a vertex form their own fan: one below the bound is left alone, as a boundary needle.
struct EdgeConstraints {
  /// #E flags, 1 on a constrained edge (entries past the end count as 0). delaunay_refine()
  /// grows it to the new edge count after every insertion; the halves of a split constrained
  /// edge are both constrained.
  std::vector<char>* flags = nullptr;
  /// Called after delaunay_refine() split constrained edge e at a new vertex v, at fraction t of
  /// its length from the tail of edge_halfedge(e) as it was: e now runs from that tail to v (the
  /// same direction), new_edge from v to the old head. May be empty.
  std::function<void(Index e, Index new_edge, Index v, double t)> on_split;
  bool is_constrained(Index e) const { return is_flagged(flags, e); }
};

/// Bytes one vertex of a refined triangulation costs, all told: the intrinsic triangulation
/// and its signposts (about 1 KiB), the Laplacian, and a later sparse Cholesky factorization
/// of it (the rest). An upper bound of the peak resident size per vertex measured on the
/// corpus (docs/decisions.md D-095).
inline constexpr double kRefineBytesPerVertex = 4096.0;

/// The default memory budget: half the machine's physical memory (sysconf(_SC_PHYS_PAGES) ×
/// page size), or 80% of the process's address-space limit (ulimit -v, RLIMIT_AS) when that is
/// lower. 4 GiB when neither can be read.
double default_memory_budget();

/// What a refinement request will cost, estimated before refining (time: one pass over the
/// faces).
///   size term:  S = 0.65 × A / max_area         (A: the faces' total area; 0 without a bound)
///   angle term: G = n_V                          (n_V: vertices before refinement)
///   insertions: I = min(max(S, G), cap)          (cap: the insertion cap, max_insertions)
///   vertices:   V = n_V + I;   bytes: B = V × kRefineBytesPerVertex
/// S: a Delaunay-refined triangulation whose triangles are all below max_area has about
/// 1.3 × A / max_area triangles, half as many vertices. G: refining to the angle bound alone
/// inserts at most about n_V on the corpus, and the size-driven insertions fix most bad angles
/// too, hence the max. The estimate is at most about 20 % under the actual insertions and may be
/// a few times over on meshes of very uneven edge lengths (docs/decisions.md D-095). The
/// insertion cap bounds every input's insertions, and with them the memory (delaunay_refine()
/// stops at the budget).
struct RefineEstimate {
  double size_term = 0.0, angle_term = 0.0;
  double insertions = 0.0;  ///< I above
  double vertices = 0.0;    ///< V above
  double bytes = 0.0;       ///< B above
  double budget = 0.0;      ///< the budget it is compared with (max_memory_bytes or default)
};

/// The estimate above for refining `tri` with `options` (validated first).
/// @throws InvalidInput on bad options
RefineEstimate estimate_refinement(const IntrinsicTriangulation& tri, const RefineOptions& options);

/// Refuses a request whose estimate exceeds the budget: throws InvalidInput stating the
/// estimate (vertices, memory), the budget and what overrides it (RefineOptions::
/// max_memory_bytes, `--memory-budget GB` in the CLI) or asks for less. Called by
/// delaunay_refine() before any work; callers may call it earlier (before building signposts).
/// @throws InvalidInput as said, or on bad options
void check_refinement_budget(const IntrinsicTriangulation& tri, const RefineOptions& options);

/// Outcome of delaunay_refine(), counted.
struct RefineReport {
  Index vertices_before = 0, vertices_after = 0;
  Index insertions = 0;            ///< vertices inserted (= face insertions + edge splits)
  Index face_insertions = 0;       ///< circumcenters inserted inside a face
  Index edge_splits = 0;           ///< circumcenters that landed on an interior edge
  Index boundary_splits = 0;       ///< boundary edges split (circumcenter across the boundary)
  Index constrained_splits = 0;    ///< constrained edges split (point across or encroaching one)
  Index constrained_floor = 0;     ///< splits of constrained edges shorter than 1/1024 of the
                                   ///< mean edge length refused (where curves meet at small
                                   ///< angles midpoint splits would cascade); the bad triangles
                                   ///< there stay (bad_faces_left)
  Index failed_traces = 0;         ///< bad triangles skipped because tracing failed
  std::size_t flips = 0;           ///< edge flips (initial Delaunay + after insertions)
  bool hit_insertion_cap = false;  ///< stopped by max_insertions
  Index needle_faces = 0;          ///< triangles left alone: each small angle sits in a vertex
                                   ///< fan (cone) whose total angle is below the bound (2×
                                   ///< bound inside; per fan at a pinched vertex), or the
                                   ///< triangle lies in the shadow of a needle: its shortest
                                   ///< side joins the two sides of a boundary (or constrained)
                                   ///< fan below the bound, where fixing it would only make a
                                   ///< smaller one nearer the apex (docs/decisions.md D-120)
  Index bad_faces_left = 0;        ///< other triangles still below the bounds at the end
                                   ///< (scale_floor_faces included)
  Index scale_floor_faces = 0;     ///< bad triangles left alone because their shortest side is
                                   ///< below 2^-20 of the local scale (the shortest input edge
                                   ///< at their vertices): insertions there were cascading
                                   ///< towards a point (min_angle_degrees above ≈ 26.5°, where
                                   ///< Chew's algorithm has no termination guarantee)
  double min_angle_before = 0.0;   ///< smallest corner angle, degrees, of the input's intrinsic
                                   ///< Delaunay triangulation (before any insertion)
  double min_angle_after = 0.0;    ///< smallest corner angle at the end, degrees (all faces)
  double min_angle_after_excluding_needles = 0.0;  ///< same, degrees, ignoring needle_faces
  /// The conforming step (RefineOptions::conform, with constraints): constrained and boundary
  /// edges split because their cotan weight was negative (also counted in insertions), of which
  /// on a concentric shell around a corner rather than at the midpoint.
  Index conforming_splits = 0, conforming_shell_splits = 0;
  bool conforming_hit_cap = false;  ///< the conforming step stopped at its cap
  /// Constrained and boundary edges whose cotan weight is still negative at the end (with
  /// constraints and conform; else not counted: 0), of which shorter than the conforming floor
  /// (2^-30 × the mean edge length: where barriers meet at small angles), and the most negative
  /// (cot α + cot β) / (|cot α| + |cot β|) over them, in [−1, 0] (0 when none).
  Index negative_barrier_weights = 0, negative_barrier_floor = 0;
  double min_relative_barrier_weight = 0.0;
};

/// Refines `st` in place: flips to intrinsic Delaunay, then repeatedly takes the worst bad
/// triangle, traces from its centroid towards its circumcenter (or off-center) over the
/// intrinsic triangulation and inserts a vertex there (or splits the edge it lands on, or the
/// boundary edge it would cross, at its midpoint), and restores the Delaunay property by
/// flips. Worst first: triangles with a corner below the bound that an insertion can fix, by
/// that corner, smallest first (in steps of about 0.25°), then triangles larger than max_area
/// or facing an encroached boundary side, largest first (why this order: docs/decisions.md
/// D-015). Terminates on every input (the insertion cap).
/// Input vertices keep their ids; inserted vertices are appended. The surface never changes.
/// With `constraints`, constrained refinement (EdgeConstraints): constrained edges are never
/// flipped or crossed, only split; the report's constrained_splits counts those splits, and
/// conforming_splits those of the final conforming step (RefineOptions::conform).
/// @throws InvalidInput on bad options (RefineOptions::validate())
RefineReport delaunay_refine(SignpostTriangulation& st, const RefineOptions& options = {},
                             EdgeConstraints* constraints = nullptr);

/// The same algorithm (the same code) on integer coordinates (intrinsic/integer/
/// normal_coordinates.h): every flip, insertion and split keeps the normal coordinates and
/// roundabouts, so inserted vertices are located on the input from the integers
/// (vertex_locations(nc)). The same calls as the signpost overload: on the same input and
/// options, the same insertions and the same edge lengths.
/// @throws InvalidInput on bad options (RefineOptions::validate())
RefineReport delaunay_refine(NormalCoordinateTriangulation& nc, const RefineOptions& options = {},
                             EdgeConstraints* constraints = nullptr);

/// The same algorithm (the same code) on a bare intrinsic triangulation, without signposts:
/// any Δ-complex — the tufted cover of a nonmanifold mesh or point cloud, or a plain manifold
/// triangulation with or without boundary. Vertices 0..n−1 keep their ids, so values solved
/// for on the result are the input vertices' first n entries; inserted vertices (ids ≥ n) have
/// no location on the input surface (use the signpost overload to know where they lie).
/// Whether a small corner can be fixed is decided by the total angle of its vertex's fan
/// (cone), as in the signpost overload: at a pinched vertex (an interior input vertex of a
/// tufted cover has two fans, front and back) each fan counts on its own, not the vertex's
/// angle sum over all fans.
/// Inserted vertices are flat (angle sum 2π, π on the boundary); a vertex is on the boundary
/// when a side without twin starts or ends at it. The multiplicity (2 for a tufted cover) is
/// kept, and with it total_area(). On a manifold mesh the result is exactly the signpost
/// overload's (same insertions, same lengths).
/// Constraints as in the signpost overload.
/// @throws InvalidInput on bad options (RefineOptions::validate())
RefineReport delaunay_refine(IntrinsicTriangulation& tri, const RefineOptions& options = {},
                             EdgeConstraints* constraints = nullptr);

/// Optimal Delaunay triangulation (ODT) relaxation of the inserted vertices.
struct RelaxOptions {
  int iterations = 1;  ///< passes over the inserted vertices (each followed by Delaunay flips); ≥ 0
  /// Keep the smallest corner angle of each star, and the sum of its triangles' smallest
  /// angles, from decreasing: a move (or its half, or quarter) that would lower either is
  /// rejected, so the triangulation's minimum angle, and with it delaunay_refine()'s bound,
  /// never gets worse (the Delaunay flips after a pass only raise it).
  bool keep_min_angle = true;
  /// After each pass's Delaunay flips, split every edge longer than this at its midpoint (the
  /// new vertices are inserted vertices: the next pass moves them), repeated until none is left,
  /// then flip to Delaunay again. Absolute, in the triangulation's length unit; 0: no splitting.
  /// Splits can lower the minimum angle (a midpoint split of a Delaunay edge at worst halves the
  /// angles next to it); the report says.
  double max_edge_length = 0.0;
  /// Cap on the splits, over all passes (−1: 10 × #vertices at the start); ≥ −1.
  Index max_splits = -1;
  /// @throws InvalidInput naming the field: iterations < 0, max_edge_length negative or not
  ///         finite, max_splits < −1
  void validate() const;
};

/// Outcome of relax_inserted_vertices(), counted.
struct RelaxReport {
  int passes = 0;
  Index moved = 0;                ///< vertex moves made (summed over the passes)
  Index rejected = 0;             ///< moves skipped: outside the star, or lowering its min angle
  Index skipped_boundary = 0;     ///< inserted boundary vertices (never moved), per pass
  Index skipped_irregular = 0;    ///< inserted vertices whose star is not a disk, per pass
  Index splits = 0;               ///< edges split for max_edge_length (new inserted vertices)
  bool hit_split_cap = false;     ///< stopped splitting at max_splits with longer edges left
  double max_edge_after = 0.0;    ///< longest edge at the end (absolute length)
  double max_displacement = 0.0;  ///< longest single move (absolute length)
  std::size_t flips = 0;          ///< Delaunay flips after the passes
  double min_angle_before = 0.0, min_angle_after = 0.0;            ///< degrees, over all faces
  double mean_min_angle_before = 0.0, mean_min_angle_after = 0.0;  ///< degrees, face mean
};

/// ODT relaxation: for `iterations` passes, moves every inserted interior vertex (ids ≥
/// n_input_vertices(); input vertices never move, inserted boundary vertices neither) to the
/// area-weighted mean of the circumcenters of its star's triangles, computed in the flat
/// layout of its star (inserted_vertex_star(), intrinsic/core/geometry.h), if that point lies
/// strictly inside the star (else half, then a quarter of the way, else not at all), then
/// flips to intrinsic Delaunay, then splits edges longer than max_edge_length (if set). The
/// surface, the input vertices' angle sums and the total area are unchanged; inserted vertices
/// stay flat and keep their locations on the input.
/// @throws InvalidInput on bad options (RelaxOptions::validate())
RelaxReport relax_inserted_vertices(SignpostTriangulation& st, const RelaxOptions& options = {});

/// The same relaxation (the same code) on integer coordinates: vertices move inside their flat
/// star with NormalCoordinateTriangulation::move_inserted_vertex() (the star keeps its edges;
/// the spokes' normal coordinates and roundabouts are recounted), so on the same triangulation
/// and options it makes the same moves, splits and flips as the signpost overload, and its
/// edge lengths agree with it to rounding. A vertex inserted on an input edge moves off it, as
/// with signposts.
/// @throws InvalidInput on bad options (RelaxOptions::validate())
RelaxReport relax_inserted_vertices(NormalCoordinateTriangulation& nc,
                                    const RelaxOptions& options = {});

/// Smallest corner angle of face f, in radians (reports give degrees).
double min_corner_angle(const IntrinsicTriangulation& tri, Index f);

}  // namespace ifem::intrinsic
