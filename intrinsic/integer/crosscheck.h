// Delaunay refinement with both correspondences on one input, compared: the cross-check of
// integer coordinates against signposts (issue 33) that the tests and `ifem_bench
// integer-crosscheck` share; docs/decisions.md D-281.
#pragma once

#include <Eigen/Core>
#include <string>

#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {

/// One Delaunay refinement run on each representation (RefineCrosscheck::Run).
struct RefineRun {
  bool ok = false;                   ///< refinement and common subdivision both succeeded
  std::string error;                 ///< what threw, when !ok
  double seconds = 0.0;              ///< delaunay_refine, wall clock
  double subdivision_seconds = 0.0;  ///< common_subdivision, wall clock
  RefineReport report;
  Index subdivision_vertices = 0, subdivision_faces = 0;
  /// The common subdivision's pieces summed per input face against that face's 3D area: the
  /// largest |Σ − area| over the input faces, relative to the mean input face area (absolute
  /// when every input face has zero area).
  double area_partition_error = 0.0;
};

/// Delaunay refinement with both correspondences on one input, compared (issue 33's
/// cross-check): where both succeed, the same insertions and the same lengths are expected.
struct RefineCrosscheck {
  RefineRun signposts, integer;
  /// Both ok, with the same insertions, face insertions and splits.
  bool same_insertions = false;
  /// Both ok: max |ℓ_signposts − ℓ_integer| over the edges (infinity when the counts differ).
  double max_length_difference = 0.0;
  /// Both ok: the largest 3D distance between the two locations of an intrinsic vertex
  /// (the common subdivisions' first #V vertices; infinity when the counts differ).
  double max_vertex_distance = 0.0;
  /// Both ok: the mean edge length after refinement (the tolerance's scale).
  double mean_length = 0.0;
  /// Both ok, the same insertions, lengths within 1e-9·mean_length and every intrinsic vertex
  /// at the same place within 1e-6·mean_length (the signposts locate inserted vertices to a few
  /// 1e-9 of the mesh size).
  bool agree() const;
};

/// Refines copies of s0 and n0 (the same input, built with the same mollification) with
/// `options`, builds both common subdivisions and compares them; catches what either throws
/// (recorded as RefineRun::error). The refined triangulations are written to s_out / n_out when
/// given (e.g. for further checks).
RefineCrosscheck crosscheck_refine(const SignpostTriangulation& s0,
                                   const NormalCoordinateTriangulation& n0,
                                   const RefineOptions& options,
                                   SignpostTriangulation* s_out = nullptr,
                                   NormalCoordinateTriangulation* n_out = nullptr);

}  // namespace ifem::intrinsic
