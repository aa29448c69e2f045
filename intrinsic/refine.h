// Intrinsic Delaunay refinement (Chew's second algorithm on a signpost intrinsic triangulation,
// Sharp, Soliman & Crane 2019, §6.2): insert circumcenters of bad triangles, located by tracing
// over the intrinsic triangulation, until every triangle meets a minimum-angle bound.
#pragma once

#include <cstddef>

#include "intrinsic/signpost.h"

namespace ifem::intrinsic {

/// What to refine towards.
struct RefineOptions {
  double min_angle_degrees = 25.0;  ///< minimum corner angle wanted, in (0, 30]
  double max_area = 0.0;            ///< also split triangles larger than this (0: no bound)
  Index max_insertions = -1;        ///< cap on inserted vertices (−1: 10 × #input vertices)
  /// Split boundary edges that face an obtuse angle (encroached: the opposite vertex lies in
  /// their diametral circle, Ruppert), until none is left. Chew's angle test alone keeps e.g.
  /// 25°-25°-130° triangles, whose boundary side gets a negative cotan weight; with this on,
  /// the refined Laplacian has non-negative weights on boundary edges too.
  bool split_encroached_boundary = true;
};

/// Outcome of delaunay_refine(), counted.
struct RefineReport {
  Index vertices_before = 0, vertices_after = 0;
  Index insertions = 0;           ///< vertices inserted (= face insertions + edge splits)
  Index face_insertions = 0;      ///< circumcenters inserted inside a face
  Index edge_splits = 0;          ///< circumcenters that landed on an interior edge
  Index boundary_splits = 0;      ///< boundary edges split (circumcenter across the boundary)
  Index failed_traces = 0;        ///< bad triangles skipped because tracing failed
  std::size_t flips = 0;          ///< edge flips (initial Delaunay + after insertions)
  bool hit_insertion_cap = false; ///< stopped by max_insertions
  Index needle_faces = 0;         ///< triangles left alone: each small angle sits at a vertex
                                  ///< whose total angle is below the bound (2× bound inside)
  Index bad_faces_left = 0;       ///< other triangles still below the bounds at the end
  double min_angle_before = 0.0;  ///< smallest corner angle, degrees, of the input's intrinsic
                                  ///< Delaunay triangulation... (before any insertion)
  double min_angle_after = 0.0;   ///< smallest corner angle at the end, degrees (all faces)
  double min_angle_after_excluding_needles = 0.0;  ///< same, ignoring needle_faces
};

/// Refines `st` in place: flips to intrinsic Delaunay, then repeatedly takes the largest bad
/// triangle (a corner below the bound, or area above max_area), traces from its centroid
/// towards its circumcenter over the intrinsic triangulation and inserts a vertex there (or
/// splits the edge it lands on, or the boundary edge it would cross, at its midpoint), and
/// restores the Delaunay property by flips. Terminates on every input (the insertion cap).
/// Input vertices keep their ids; inserted vertices are appended.
/// @throws InvalidInput on a bound outside (0, 30] degrees or a negative max_area
RefineReport delaunay_refine(SignpostTriangulation& st, const RefineOptions& options = {});

/// Smallest corner angle (radians) of face f.
double min_corner_angle(const IntrinsicTriangulation& tri, Index f);

}  // namespace ifem::intrinsic
