// Intrinsic simplification: coarsening an intrinsic triangulation by removing vertices in the
// space of intrinsic triangulations (Liu, Gillespie, Chislett, Sharp, Jacobson, Crane 2023,
// "Surface Simplification using Intrinsic Error Metrics"; Shoemaker, Sartor, Peers 2023), with
// every removed vertex tracked as a point of a coarse face, so the coarse surface keeps a map to
// the fine one (prolongation: fem/prolongation.h). docs/decisions.md D-220..D-223, D-325, D-345.
#pragma once

#include <vector>

#include "intrinsic/core/progress.h"
#include "intrinsic/core/surface_point.h"
#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic {

/// Options of simplify(). Exactly one of target_vertices and ratio is set.
struct SimplifyOptions {
  /// Stop when this many vertices are left (> 0, < #V of the input), or 0 (use ratio).
  Index target_vertices = 0;
  /// Keep this fraction of the vertices, in (0, 1] (target = max(1, round(ratio·#V))), or 0.
  double ratio = 0.0;
  /// Progress, stage "simplify": removals made over removals asked for, 1 when done.
  ProgressCallback on_progress;
  /// @throws InvalidInput naming the field (both set, neither set, out of range)
  void validate() const;
};

/// What simplify() did, counted.
struct SimplifyReport {
  Index vertices_before = 0;    ///< #V of the input (unreferenced vertices included)
  Index vertices_after = 0;     ///< #V of the coarse triangulation
  Index removals = 0;           ///< vertices removed (interior and boundary)
  Index boundary_removals = 0;  ///< of which on a boundary (an ear cut off)
  /// Fans removed by flattening (their link polygon laid out convex and triangulated: the
  /// vertex's angle defect moves to its neighbours), where flips to 3 faces do not suffice.
  Index flattened = 0;
  /// Pillows deleted: closed fans of two faces glued along all three sides (an isolated
  /// triangle of a nonmanifold mesh or point cloud, zipped to its back), whose area is dropped;
  /// on the tufted cover any closed fan that is a closed surface of its own.
  Index pillows = 0;
  std::size_t flips = 0;  ///< edge flips: to degree 3 / to an ear, and Delaunay repair
  /// Vertices left because none could be removed without breaking a guarantee (the target was
  /// not reached): 0 when vertices_after reached the target.
  Index stuck = 0;
  double area_before = 0.0;  ///< total_area() of the input
  /// Largest relative change of a component's area before the final rescale (the removals'
  /// local metric changes, summed); the rescale makes it 0 up to round-off.
  double area_change_before_rescale = 0.0;
};

/// A coarse intrinsic triangulation and its map to the fine one.
struct Simplification {
  IntrinsicTriangulation coarse;      ///< vertices renumbered 0..#Vc−1 (in fine id order)
  std::vector<Index> coarse_to_fine;  ///< #Vc: the fine vertex each coarse vertex is
  /// #V fine: each fine vertex as a point of `coarse` (face + barycentric coordinates, all ≥ 0,
  /// summing to 1); a kept vertex is a corner with coordinate 1. An unreferenced fine vertex
  /// (no face) is kept, as an unreferenced coarse vertex, with face = kInvalidIndex.
  std::vector<SurfacePoint> fine_in_coarse;
  SimplifyReport report;
};

/// Removes vertices of `fine` greedily, cheapest first (costs refreshed lazily, when a vertex
/// whose star changed comes out of the queue), until the target is reached. Costs are compared
/// in buckets of relative width 1.5 and 1.33 (alternately), ties broken by a breadth-first order
/// of the faces from face 0, so that the removals sweep the surface whatever the input's vertex
/// order (docs/decisions.md D-340).
///
/// Algorithm: the input is flipped to intrinsic Delaunay. A vertex's cost is the area of its
/// star times (|angle defect| + the mean curvature density of its component, 4π/area): flat
/// vertices first, then in order of the area they would coarsen (uniform coarsening on a
/// uniformly curved surface). An interior vertex is flipped to degree 3 and removed; its three
/// outer sides keep their lengths and become one face. A boundary vertex whose interior angle is
/// below π is flipped to one face (an ear), which is cut off. After every removal the new sides
/// are flipped back to Delaunay. Removed vertices, and the points already inside the faces a
/// flip or removal rewrites, are carried over in the 2D layouts of those faces.
///
/// Flattening, where flips cannot make 3 faces: the fan's link polygon (its outer sides, lengths
/// kept) is laid out convex in the plane, inscribed in a circle, and triangulated (no new side
/// from a vertex to itself); v goes to the mean of the corners weighted by 1 / spoke length and
/// each old face maps linearly onto (that point, its outer side), so the map stays bijective.
/// The vertex's angle defect moves to its neighbours and the star's area changes (the cost
/// charges it; the rescale below restores each component's total). It is used from the start
/// for a vertex with several fans or a fan of angle sum ≥ 3π (which no three faces can
/// replace), and for any closed fan only in a second pass, when the first misses the target —
/// so a manifold mesh that reaches its target by flips keeps the metric as before. Fans of two
/// faces whose outer sides differ in length get one outer side flipped (three faces); a link
/// whose longest side is not below the others' sum gets that side flipped outwards (twice at
/// most). Self-edges at a vertex (it would be on its own link) are flipped away first where
/// their diamond is strictly convex. A pillow — a closed fan of two faces glued along all three
/// sides (an isolated triangle of a nonmanifold mesh or point cloud, zipped to its back) — is
/// deleted with the vertex when its two other corners keep another fan (its area is dropped,
/// its points go where the vertex goes). Flips keep four distinct vertices in their diamond.
/// On the tufted cover (multiplicity > 1) also (docs/decisions.md D-345): a pillow is any closed
/// fan that is a closed surface of its own (every outer side glued to another outer side of
/// the fan); a pillow corner left without a fan is removed with the vertex (it goes where the
/// vertex goes; never below the target); a vertex whose fans are all pillows goes to a corner
/// of one that keeps a fan; and a fan of two faces (v, a, b), (v, b, a) whose outer sides differ
/// in length gets both sides (and their partners) one length, the mean clamped to what the four
/// faces allow, where the faces across are v's own (removed with it) or the lengths agree to
/// 1 %: then it is zipped (a metric change in v's star, restored in total by the rescale).
/// simplify() never makes a self-edge; an input without one (a point cloud's cover built with
/// pointcloud::PointCloudOptions::self_edges = false, as `ifem simplify` does) keeps none.
///
/// Guarantees (tested): the coarse triangulation validates (every face satisfies the triangle
/// inequality with a margin); each component keeps its Euler characteristic (see multi-fan
/// vertices below), its boundary loops
/// (each with ≥ 3 vertices) and at least 4 vertices if closed; Gauss–Bonnet holds (a property
/// of every valid triangulation); each component's total area equals the input's (up to
/// round-off): a removal changes the metric locally (a curved vertex's star and the face(s)
/// replacing it differ in area; a cut ear or a pillow loses its area), and one uniform scale
/// per component at the end restores the area (angles, and so the Delaunay property and the
/// curvature, unchanged; the cotan Laplacian is scale invariant). Boundary length is not kept
/// (an ear's two sides become its third).
///
/// A vertex with several fans (a pinch; every vertex of the tufted cover of a manifold, which is
/// two copies) is removed from all its fans at once (it then lies in its first fan that is not
/// a pillow); that raises the Euler characteristic by (fans − 1) and can split a component at
/// the pinch, so both are kept where no such vertex is removed. A vertex stays (counted in
/// report.stuck when the target is missed) when it has a self-edge that cannot be flipped away,
/// a boundary fan among several or at an angle ≥ π, a fan of two faces that cannot be zipped or
/// opened, no polygon or triangulation keeping the margin (a link running between two
/// neighbours only has none without a self-edge), a boundary loop at 3 vertices or a closed
/// component at 4 vertices. So no valid input is refused for numerical reasons
/// (docs/decisions.md D-222, D-325).
/// The multiplicity (2 on a tufted cover) is kept. simplify(result.coarse) coarsens again.
/// @throws InvalidInput on bad options (SimplifyOptions::validate()), or a target ≥ #V
Simplification simplify(const IntrinsicTriangulation& fine, const SimplifyOptions& options);

}  // namespace ifem::intrinsic
