// Conforming step of constrained refinement (used by delaunay_refine(), RefineOptions::conform):
// splits constrained and boundary edges ("barrier" edges) whose cotan weight is negative until
// every weight is ≥ 0, so that the refined Laplacian is an M-matrix and the discrete maximum
// principle holds (docs/decisions.md D-140).
//
// A barrier edge e with opposite angles α (and β across it; none on the boundary) has weight
// (cot α + cot β)/2 < 0 iff α + β > π (boundary: α > π/2); then one of its apexes lies inside e's
// diametral circle. The step splits e (at its midpoint, or on a concentric shell, below), lets
// Delaunay flips repair the unconstrained edges around the new vertex, and checks the barrier
// sides of every face that changed, until none is negative.
//
// Split point (Ruppert's concentric shells): when exactly one end of e is a "corner" (a vertex
// that existed before refinement: input vertices, curve waypoints, where barriers may meet at
// any angle), e is split at the power of two (of the length unit) nearest to half its length,
// measured from that corner (fraction in [1/(2√2), 1/√2]); otherwise at its midpoint. Barriers
// meeting at a corner at a small angle are then cut at the same radii, so the triangles between
// them become isosceles with base angles below π/2, and the splits stop.
//
// What is proven: the step terminates (every split edge is at least `floor` long and its pieces
// at least 0.29 × as long, so each barrier of length L is split at most about 3.5 L / floor
// times; and the cap). When it ends with negative_left = 0, every barrier weight is ≥ 0 and,
// since the flips leave every unconstrained interior edge Delaunay, every cotan weight is ≥ 0.
// What is not: that the floor is never reached. Where two barriers meet at a small angle at a
// vertex that is not flat, or the apex sits on another barrier at a tiny distance, splits can
// reach the floor; those edges keep a negative weight and are counted (negative_left, with the
// most negative relative weight), they are all shorter than the floor.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "intrinsic/core/triangulation.h"

namespace ifem::intrinsic::detail {

/// What the conforming step needs from the refinement host.
struct ConformHost {
  const IntrinsicTriangulation& tri;
  const std::vector<char>* flags;  ///< constrained edges (may be null: boundary edges only)
  /// splits edge e at fraction t from the tail of edge_halfedge(e), keeping the constraints
  /// (flags grown, the far half constrained too); returns the new vertex, or kInvalidIndex when
  /// it made none
  std::function<Index(Index e, double t)> split;
  /// local Delaunay repair from the queued edges (never flipping constrained ones), appending
  /// the faces of every flip to `touched`; returns the number of flips
  std::function<std::size_t(const std::vector<Index>& queue, std::vector<Index>* touched)>
      flip_from;
  Index first_inserted = 0;  ///< vertices with smaller ids are corners (shell centres)
  double floor = 0.0;        ///< barrier edges shorter than this are not split (absolute)
  Index max_splits = 0;      ///< cap on splits
};

/// Outcome of conform_barriers().
struct ConformOutcome {
  Index splits = 0;        ///< barrier edges split
  Index shell_splits = 0;  ///< of which on a concentric shell (not at the midpoint)
  std::size_t flips = 0;
  bool hit_cap = false;
  Index negative_left = 0;  ///< barrier edges with a negative weight at the end
  Index floor_left = 0;     ///< of which shorter than the floor
  /// the most negative (cot α + cot β) / (|cot α| + |cot β|) over those edges, in [−1, 0]
  /// (0 when none is left)
  double min_relative_weight = 0.0;
};

/// Whether barrier edge e's cotan weight is negative: cot α + cot β < −1e-12 (|cot α| + |cot β|)
/// (β absent on a boundary edge). Writes that relative weight to *relative when given.
bool negative_weight(const IntrinsicTriangulation& tri, Index e, double* relative = nullptr);

/// The conforming step described above.
ConformOutcome conform_barriers(const ConformHost& host);

}  // namespace ifem::intrinsic::detail
